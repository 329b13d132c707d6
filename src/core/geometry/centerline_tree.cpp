#include "endovascular_sim/geometry/centerline_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace evsim {
namespace {

/// A point of an overlapping line within this fraction of its radius of
/// the tree built so far runs along it (layout a).
constexpr double kShared = 0.25;
/// Points closer than this coincide [m].
constexpr double kWeld = 1e-9;

std::string mm(const Vec3& p) {
  std::ostringstream s;
  s.precision(4);
  s << "(" << p.x() * 1e3 << ", " << p.y() * 1e3 << ", " << p.z() * 1e3 << ") mm";
  return s.str();
}

/// Vertices joined by edges; a vertex keeps the branch id of its cell.
struct Graph {
  std::vector<Vec3> x;
  std::vector<double> r;
  std::vector<int> id;  // the file's branch id (or outlet index), -1 none
  std::vector<std::vector<int>> adj;

  int add(const Vec3& p, double radius, int branch) {
    x.push_back(p);
    r.push_back(radius);
    id.push_back(branch);
    adj.emplace_back();
    return static_cast<int>(x.size()) - 1;
  }
  void join(int a, int b) {
    if (a == b || std::find(adj[a].begin(), adj[a].end(), b) != adj[a].end()) return;
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
};

/// Uniform grid of vertices (cell size h [m]) for the nearest-vertex query.
class VertexGrid {
 public:
  explicit VertexGrid(double h) : h_(h) {}
  void insert(const Vec3& p, int v) { cells_[key(p, 0, 0, 0)].push_back(v); }
  /// Vertices within the 27 cells around p.
  template <typename F>
  void near(const Vec3& p, F&& visit) const {
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k) {
          const auto it = cells_.find(key(p, i, j, k));
          if (it == cells_.end()) continue;
          for (int v : it->second) visit(v);
        }
  }

 private:
  long long key(const Vec3& p, int i, int j, int k) const {
    const long long a = static_cast<long long>(std::floor(p.x() / h_)) + i;
    const long long b = static_cast<long long>(std::floor(p.y() / h_)) + j;
    const long long c = static_cast<long long>(std::floor(p.z() / h_)) + k;
    return (a * 73856093LL) ^ (b * 19349663LL) ^ (c * 83492791LL);
  }
  double h_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b, double* t = nullptr) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  if (t) *t = s;
  return (p - (a + s * ab)).norm();
}

void checkInput(const CenterlinePolylines& in) {
  if (in.points.empty()) throw std::invalid_argument("no points: the file is empty");
  if (in.radius.size() != in.points.size())
    throw std::invalid_argument("the radius array has " + std::to_string(in.radius.size()) +
                                " values for " + std::to_string(in.points.size()) + " points");
  for (size_t i = 0; i < in.points.size(); ++i) {
    if (!in.points[i].allFinite())
      throw std::invalid_argument("point " + std::to_string(i) + " is not finite");
    if (in.points[i].cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw std::invalid_argument("point " + std::to_string(i) +
                                  " lies beyond 10 m of the origin: check the units");
    if (in.radius[i] > kMaxVesselRadius) {
      std::ostringstream why;
      why << "the radius of point " << i << " is " << in.radius[i]
          << " m, beyond the largest vessel radius (" << kMaxVesselRadius << " m): check the units";
      throw std::invalid_argument(why.str());
    }
    if (!(std::isfinite(in.radius[i]) && in.radius[i] > 0.0)) {
      std::ostringstream why;
      why << "the radius of point " << i << " at " << mm(in.points[i]) << " is " << in.radius[i]
          << ": radii must be positive and finite";
      throw std::invalid_argument(why.str());
    }
  }
  int usable = 0;
  for (const auto& line : in.lines) {
    for (int p : line)
      if (p < 0 || p >= static_cast<int>(in.points.size()))
        throw std::invalid_argument("a line refers to point " + std::to_string(p) + " of " +
                                    std::to_string(in.points.size()));
    usable += line.size() >= 2;
  }
  if (usable == 0) throw std::invalid_argument("no lines of two or more points");
}

/// One vertex per distinct position (points within kWeld coincide).
std::vector<int> weld(const CenterlinePolylines& in, Graph* g) {
  std::vector<int> vertex(in.points.size(), -1);
  VertexGrid grid(1e-6);
  for (size_t l = 0; l < in.lines.size(); ++l)
    for (int p : in.lines[l]) {
      if (vertex[p] >= 0) continue;
      int same = -1;
      grid.near(in.points[p], [&](int v) {
        if ((g->x[v] - in.points[p]).norm() <= kWeld) same = v;
      });
      if (same < 0) {
        same = g->add(in.points[p], in.radius[p], in.branch_id.empty() ? -1 : in.branch_id[l]);
        grid.insert(in.points[p], same);
      }
      vertex[p] = same;
    }
  return vertex;
}

/// Layout (a): no vertex is shared by two lines except as both lines' first.
bool overlapping(const CenterlinePolylines& in, const std::vector<int>& vertex) {
  int lines = 0;
  std::unordered_map<int, int> first_user;  // vertex -> line, or -2 when shared otherwise
  for (size_t l = 0; l < in.lines.size(); ++l) {
    if (in.lines[l].size() < 2) continue;
    ++lines;
    for (size_t k = 0; k < in.lines[l].size(); ++k) {
      const int v = vertex[in.lines[l][k]];
      auto it = first_user.find(v);
      if (it == first_user.end()) {
        first_user[v] = k == 0 ? static_cast<int>(l) : -1 - static_cast<int>(l);
        continue;
      }
      const int owner = it->second >= 0 ? it->second : -1 - it->second;
      if (owner == static_cast<int>(l)) continue;
      if (!(k == 0 && it->second >= 0)) return false;  // shared in the middle: a merged tree
    }
  }
  return lines >= 2;
}

double arcLength(const CenterlinePolylines& in, const std::vector<int>& line) {
  double s = 0.0;
  for (size_t k = 1; k < line.size(); ++k)
    s += (in.points[line[k]] - in.points[line[k - 1]]).norm();
  return s;
}

/// Layout (a): the lines merged, longest first; each line's vertices carry
/// its index in the file (its outlet).
void mergeOverlapping(const CenterlinePolylines& in, double tolerance, Graph* g) {
  std::vector<int> order;
  for (size_t l = 0; l < in.lines.size(); ++l)
    if (in.lines[l].size() >= 2) order.push_back(static_cast<int>(l));
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return arcLength(in, in.lines[a]) > arcLength(in, in.lines[b]);
  });
  const double r_max = *std::max_element(in.radius.begin(), in.radius.end());
  VertexGrid grid(std::max(kShared * r_max, 1e-5));
  auto append = [&](int line, size_t from, int attach) {
    int prev = attach;
    for (size_t k = from; k < in.lines[line].size(); ++k) {
      const int p = in.lines[line][k];
      const int v = g->add(in.points[p], in.radius[p], line);
      grid.insert(in.points[p], v);
      if (prev >= 0) g->join(prev, v);
      prev = v;
    }
  };
  append(order[0], 0, -1);
  for (size_t o = 1; o < order.size(); ++o) {
    const std::vector<int>& line = in.lines[order[o]];
    std::vector<int> nearest;  // per point along the tree: its nearest tree vertex
    std::vector<double> gap;   // and its distance to the tree [m]
    for (size_t k = 0; k < line.size(); ++k) {
      const Vec3& p = in.points[line[k]];
      double best = std::numeric_limits<double>::infinity();
      int closest = -1;
      grid.near(p, [&](int v) {
        double d = (g->x[v] - p).norm();
        for (int w : g->adj[v]) d = std::min(d, segmentDistance(p, g->x[v], g->x[w]));
        if (d < best) best = d, closest = v;
      });
      if (best > kShared * in.radius[line[k]]) break;
      nearest.push_back(closest);
      gap.push_back(best);
    }
    if (nearest.size() == line.size()) continue;  // wholly along the tree
    if (nearest.empty())
      throw std::invalid_argument("line " + std::to_string(order[o]) +
                                  " does not start on the others (layout of one line per outlet, "
                                  "each from the inlet)");
    // The line separates gradually: it branches where its distance to the
    // tree last was that of the shared stretch (twice its median, plus the
    // tolerance), not where it leaves the tube.
    std::vector<double> sorted = gap;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double shared = 2.0 * sorted[sorted.size() / 2] + tolerance;
    size_t j = gap.size() - 1;
    while (j > 0 && gap[j] > shared) --j;
    append(order[o], j + 1, nearest[j]);
  }
}

/// Layout (b): the cells joined at shared vertices.
void joinCells(const CenterlinePolylines& in, const std::vector<int>& vertex, Graph* g) {
  for (const auto& line : in.lines)
    for (size_t k = 1; k < line.size(); ++k) g->join(vertex[line[k - 1]], vertex[line[k]]);
}

/// Connected pieces, largest (by length) first.
std::vector<std::vector<int>> pieces(const Graph& g, std::vector<double>* lengths) {
  std::vector<int> seen(g.x.size(), 0);
  std::vector<std::vector<int>> out;
  for (size_t s = 0; s < g.x.size(); ++s) {
    if (seen[s] || g.adj[s].empty()) continue;
    std::vector<int> piece{static_cast<int>(s)};
    seen[s] = 1;
    for (size_t i = 0; i < piece.size(); ++i)
      for (int w : g.adj[piece[i]])
        if (!seen[w]) seen[w] = 1, piece.push_back(w);
    out.push_back(piece);
  }
  lengths->clear();
  for (const auto& piece : out) {
    double len = 0.0;
    for (int v : piece)
      for (int w : g.adj[v]) len += 0.5 * (g.x[v] - g.x[w]).norm();
    lengths->push_back(len);
  }
  std::vector<size_t> idx(out.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(),
            [&](size_t a, size_t b) { return (*lengths)[a] > (*lengths)[b]; });
  std::vector<std::vector<int>> sorted;
  std::vector<double> sorted_len;
  for (size_t i : idx) sorted.push_back(out[i]), sorted_len.push_back((*lengths)[i]);
  *lengths = sorted_len;
  return sorted;
}

/// A branch: vertices from its first (the inlet, or a junction of its
/// parent branch) to its last (an end or a junction).
struct Branch {
  std::vector<int> v;
  int parent{-1};  // branch index
  int id{-1};
};

/// Walks the piece from the inlet; throws on a loop.
std::vector<Branch> branchesFrom(const Graph& g, int inlet) {
  std::vector<Branch> out;
  std::vector<int> seen(g.x.size(), 0);
  std::vector<std::pair<int, int>> pending;  // (first edge's far vertex, from vertex)
  std::vector<int> pending_parent;           // and the branch it leaves
  seen[inlet] = 1;
  for (int w : g.adj[inlet]) pending.push_back({w, inlet}), pending_parent.push_back(-1);
  while (!pending.empty()) {
    auto [v, from] = pending.back();
    const int parent = pending_parent.back();
    pending.pop_back();
    pending_parent.pop_back();
    Branch b;
    b.parent = parent;
    b.v = {from};
    int prev = from;
    while (true) {
      if (seen[v])
        throw std::invalid_argument("the centreline has a loop through " + mm(g.x[v]) +
                                    ": a vessel tree has none");
      seen[v] = 1;
      b.v.push_back(v);
      if (g.adj[v].size() != 2) break;
      const int next = g.adj[v][0] == prev ? g.adj[v][1] : g.adj[v][0];
      prev = v;
      v = next;
    }
    out.push_back(b);
    const int self = static_cast<int>(out.size()) - 1, last = b.v.back();
    for (int w : g.adj[last])
      if (w != prev) pending.push_back({w, last}), pending_parent.push_back(self);
  }
  return out;
}

/// Branch ids: the id most of a branch's vertices carry from the file,
/// claimed by the branches ending at an outlet first (layout a: the outlet's
/// line index), then by the others; a branch left without one gets the next
/// free id, in the walk's order.
void assignIds(const Graph& g, std::vector<Branch>* branches) {
  std::map<int, int> taken;
  int next = 0;
  for (const Branch& b : *branches)
    for (int v : b.v) next = std::max(next, g.id[v] + 1);
  std::vector<size_t> order;
  for (int pass = 0; pass < 2; ++pass)
    for (size_t i = 0; i < branches->size(); ++i)
      if ((g.adj[(*branches)[i].v.back()].size() == 1) == (pass == 0)) order.push_back(i);
  for (size_t i : order) {
    Branch& b = (*branches)[i];
    std::map<int, int> votes;
    for (size_t k = 1; k < b.v.size(); ++k)
      if (g.id[b.v[k]] >= 0) ++votes[g.id[b.v[k]]];
    int most = 0;
    for (auto [candidate, count] : votes)
      if (count > most && !taken.count(candidate)) b.id = candidate, most = count;
    if (b.id >= 0) taken[b.id] = static_cast<int>(i);
  }
  for (Branch& b : *branches)
    if (b.id < 0) b.id = next++;
}

/// Running median of the radii over one radius of arc length.
std::vector<double> smoothRadii(const Graph& g, const std::vector<int>& v) {
  std::vector<double> s(v.size(), 0.0), out(v.size());
  for (size_t k = 1; k < v.size(); ++k) s[k] = s[k - 1] + (g.x[v[k]] - g.x[v[k - 1]]).norm();
  for (size_t k = 0; k < v.size(); ++k) {
    std::vector<double> window;
    const double half = 0.5 * g.r[v[k]];
    for (size_t j = 0; j < v.size(); ++j)
      if (std::abs(s[j] - s[k]) <= half) window.push_back(g.r[v[j]]);
    std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
    out[k] = window[window.size() / 2];
  }
  return out;
}

/// Douglas-Peucker on axis and radius: the kept indices of v.
void simplify(const Graph& g, const std::vector<int>& v, const std::vector<double>& r,
              const CenterlineTreeOptions& o, size_t a, size_t b, std::vector<char>* keep,
              CenterlineTreeReport* report) {
  if (b <= a + 1) return;
  double worst = 1.0;
  size_t split = 0;
  for (size_t i = a + 1; i < b; ++i) {
    double t = 0.0;
    const double axis = segmentDistance(g.x[v[i]], g.x[v[a]], g.x[v[b]], &t);
    const double radius = std::abs(r[i] - ((1.0 - t) * r[a] + t * r[b])) / r[i];
    const double score = std::max(axis / o.tolerance, radius / o.radius_tolerance);
    if (score > worst) worst = score, split = i;
  }
  if (split == 0) {
    for (size_t i = a + 1; i < b; ++i) {
      double t = 0.0;
      report->max_axis_error =
          std::max(report->max_axis_error, segmentDistance(g.x[v[i]], g.x[v[a]], g.x[v[b]], &t));
      report->max_radius_error =
          std::max(report->max_radius_error, std::abs(r[i] - ((1.0 - t) * r[a] + t * r[b])) / r[i]);
    }
    return;
  }
  (*keep)[split] = 1;
  simplify(g, v, r, o, a, split, keep, report);
  simplify(g, v, r, o, split, b, keep, report);
}

/// Warns where a radius reaches the centreline of another branch: their
/// lumens merge in the surface. Two branches that meet at a junction J (a
/// parent and its child, or two siblings) are compared only away from it
/// (both points more than two radii of J from J), where a fork's lumens
/// part.
void warnCrowdedBranches(const Centerline& c, const std::vector<int>& branch_of,
                         const std::vector<Branch>& branches, CenterlineTreeReport* report) {
  const int nb = static_cast<int>(branches.size());
  std::vector<int> junction(nb, -1);  // the tree point each branch leaves from
  for (int i = 0; i < c.numPoints(); ++i) {
    const int p = c.parent[i];
    if (p >= 0 && branch_of[p] != branch_of[i] && junction[branch_of[i]] < 0)
      junction[branch_of[i]] = p;
  }
  auto shared = [&](int a, int b) {  // the junction a and b meet at, or -1
    if (junction[a] >= 0 && junction[a] == junction[b]) return junction[a];
    if (junction[b] >= 0 && branch_of[junction[b]] == a) return junction[b];
    if (junction[a] >= 0 && branch_of[junction[a]] == b) return junction[a];
    return -1;
  };
  int warned = 0;
  for (int i = 0; i < c.numPoints() && warned < 3; ++i)
    for (int j = 0; j < c.numPoints(); ++j) {
      const int a = branch_of[i], b = branch_of[j];
      if (a == b) continue;
      const double d = (c.position[i] - c.position[j]).norm();
      if (d >= c.radius[i]) continue;
      const int J = shared(a, b);
      if (J >= 0 && ((c.position[i] - c.position[J]).norm() < 2.0 * c.radius[J] ||
                     (c.position[j] - c.position[J]).norm() < 2.0 * c.radius[J]))
        continue;
      std::ostringstream w;
      w << "the radius " << c.radius[i] * 1e3 << " mm of " << c.vessel_names[c.vessel[i]] << " at "
        << mm(c.position[i]) << " reaches the centreline of " << c.vessel_names[c.vessel[j]] << " "
        << d * 1e3 << " mm away: their lumens merge";
      report->warnings.push_back(w.str());
      ++warned;
      break;
    }
}

/// The warning for the disconnected pieces dropped (all but the largest).
std::string droppedPieces(const Graph& g, const std::vector<std::vector<int>>& parts,
                          const std::vector<double>& lengths) {
  std::ostringstream w;
  w << "kept the largest of " << parts.size() << " disconnected pieces (" << lengths[0] * 1e3
    << " mm); dropped:";
  for (size_t i = 1; i < parts.size() && i < 6; ++i)
    w << (i > 1 ? "," : "") << " " << parts[i].size() << " points (" << lengths[i] * 1e3
      << " mm) near " << mm(g.x[parts[i][0]]);
  if (parts.size() > 6) w << ", ...";
  return w.str();
}

/// The inlet: the end of the piece nearest the declared inlet, else the
/// widest end. Throws for a piece without ends (a loop).
int inletOf(const Graph& g, const std::vector<int>& piece, const CenterlineTreeOptions& o) {
  int inlet = -1;
  for (int v : piece) {
    if (g.adj[v].size() != 1) continue;
    const bool better =
        inlet < 0 || (o.has_inlet ? (g.x[v] - o.inlet).norm() < (g.x[inlet] - o.inlet).norm()
                                  : g.r[v] > g.r[inlet]);
    if (better) inlet = v;
  }
  if (inlet < 0)
    throw std::invalid_argument("the centreline has a loop through " + mm(g.x[piece[0]]) +
                                ": a vessel tree has none");
  return inlet;
}

/// Every branch id the options name exists (else the error lists them).
void checkNamedBranches(const std::vector<Branch>& branches, const CenterlineTreeOptions& o) {
  for (const auto& [id, name] : o.names) {
    bool found = false;
    for (const Branch& b : branches) found = found || b.id == id;
    if (found) continue;
    std::string ids;
    for (const Branch& b : branches) ids += (ids.empty() ? "" : ", ") + std::to_string(b.id);
    throw std::invalid_argument("names: no branch " + std::to_string(id) + " (" + name +
                                ") in the tree; its branches: " + ids);
  }
}

}  // namespace

Centerline buildCenterlineTree(const CenterlinePolylines& in, const CenterlineTreeOptions& o,
                               CenterlineTreeReport* report) {
  *report = CenterlineTreeReport{};
  checkInput(in);
  if (!(o.tolerance > 0.0) || !(o.radius_tolerance > 0.0))
    throw std::invalid_argument("the tolerances must be positive");
  report->file_points = static_cast<int>(in.points.size());
  Graph g;
  const std::vector<int> vertex = weld(in, &g);
  report->overlapping = overlapping(in, vertex);
  if (report->overlapping) {
    g = Graph{};
    mergeOverlapping(in, o.tolerance, &g);
  } else {
    joinCells(in, vertex, &g);
  }

  std::vector<double> lengths;
  const std::vector<std::vector<int>> parts = pieces(g, &lengths);
  if (parts.empty()) throw std::invalid_argument("no lines of two or more points");
  if (parts.size() > 1) report->warnings.push_back(droppedPieces(g, parts, lengths));
  std::vector<Branch> branches = branchesFrom(g, inletOf(g, parts[0], o));
  assignIds(g, &branches);
  checkNamedBranches(branches, o);

  Centerline c;
  std::vector<int> out_of(g.x.size(), -1), branch_of;
  for (size_t bi = 0; bi < branches.size(); ++bi) {
    const Branch& b = branches[bi];
    const auto named = o.names.find(b.id);
    c.vessel_names.push_back(named != o.names.end() ? named->second
                                                    : "branch_" + std::to_string(b.id));
    report->branch_ids.push_back(b.id);
    const std::vector<double> r = smoothRadii(g, b.v);
    std::vector<char> keep(b.v.size(), 0);
    keep.front() = keep.back() = 1;
    simplify(g, b.v, r, o, 0, b.v.size() - 1, &keep, report);
    for (size_t k = 0; k < b.v.size(); ++k) {
      if (!keep[k]) continue;
      const int v = b.v[k];
      if (k == 0 && out_of[v] >= 0) continue;  // the junction: its parent branch's point
      const int parent = k == 0 ? -1 : out_of[b.v[0]];
      int up = parent;
      if (k > 0)
        for (size_t j = k; j-- > 0;)
          if (keep[j]) {
            up = out_of[b.v[j]];
            break;
          }
      out_of[v] = c.numPoints();
      c.position.push_back(g.x[v]);
      c.radius.push_back(r[k]);
      c.parent.push_back(k == 0 ? -1 : up);
      c.type.push_back(0);
      c.vessel.push_back(static_cast<int>(bi));
      branch_of.push_back(static_cast<int>(bi));
    }
  }
  report->points = c.numPoints();
  report->branches = static_cast<int>(branches.size());
  warnCrowdedBranches(c, branch_of, branches, report);
  return c;
}

}  // namespace evsim
