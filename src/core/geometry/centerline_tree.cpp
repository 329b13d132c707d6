// A vessel tree from the polylines of a patient's centreline (VMTK,
// SimVascular; read by scene/centerline_vtk.h), without VTK. Declared and
// documented in endovascular_sim/geometry/centerline_tree.h.
#include "endovascular_sim/geometry/centerline_tree.h"

#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "centerline_graph.h"

namespace evsim {
namespace {

using namespace centerline_graph;  // NOLINT: the graph the tree is built on

void checkInput(const CenterlinePolylines& in) {
  if (in.points.empty()) throw std::invalid_argument("no points: the file is empty");
  if (!in.point_group.empty() && in.point_group.size() != in.points.size())
    throw std::invalid_argument("the tracts' groups cover " +
                                std::to_string(in.point_group.size()) + " of " +
                                std::to_string(in.points.size()) + " points");
  if (in.radius.size() != in.points.size())
    throw std::invalid_argument("the radius array has " + std::to_string(in.radius.size()) +
                                " values for " + std::to_string(in.points.size()) + " points");
  // Every bad point at once (the first ten, and how many more).
  std::vector<std::string> bad;
  for (size_t i = 0; i < in.points.size(); ++i) {
    std::ostringstream why;
    if (!in.points[i].allFinite())
      why << "point " << i << " is not finite";
    else if (in.points[i].cwiseAbs().maxCoeff() > kMaxCoordinate)
      why << "point " << i << " lies beyond 10 m of the origin: check the units";
    else if (in.radius[i] > kMaxVesselRadius)
      why << "the radius of point " << i << " is " << in.radius[i]
          << " m, beyond the largest vessel radius (" << kMaxVesselRadius << " m): check the units";
    else if (!(std::isfinite(in.radius[i]) && in.radius[i] > 0.0))
      why << "the radius of point " << i << " at " << mm(in.points[i]) << " is " << in.radius[i]
          << ": radii must be positive and finite";
    if (!why.str().empty()) bad.push_back(why.str());
  }
  if (!bad.empty()) {
    std::string all;
    for (size_t k = 0; k < bad.size() && k < 10; ++k) all += (k ? "; " : "") + bad[k];
    if (bad.size() > 10) all += "; and " + std::to_string(bad.size() - 10) + " more";
    throw std::invalid_argument(all);
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

/// The vessel of each branch: its own, or, for a name the options give to
/// several branches, one vessel for their chain (each the continuation of
/// the one before: a segmentation splits the arch at every ostium). Fills
/// the vessel names; throws when a name's branches are no chain.
std::vector<int> branchVessels(const std::vector<Branch>& branches, const CenterlineTreeOptions& o,
                               std::vector<std::string>* names) {
  std::vector<int> vessel_of(branches.size(), -1);
  std::map<std::string, int> vessel_named;  // name -> vessel
  std::map<std::string, int> last_of;       // name -> the chain's last branch so far
  for (size_t bi = 0; bi < branches.size(); ++bi) {
    const Branch& b = branches[bi];
    const auto named = o.names.find(b.id);
    const std::string name =
        named != o.names.end() ? named->second : "branch_" + std::to_string(b.id);
    const auto known = vessel_named.find(name);
    if (known == vessel_named.end()) {
      vessel_named[name] = static_cast<int>(names->size());
      last_of[name] = static_cast<int>(bi);
      vessel_of[bi] = static_cast<int>(names->size());
      names->push_back(name);
      continue;
    }
    // Branches come parent first: this one must continue the chain's last.
    const Branch& last = branches[last_of[name]];
    if (b.parent != last_of[name])
      throw std::invalid_argument(
          "names: '" + name + "' names branches " + std::to_string(last.id) + " and " +
          std::to_string(b.id) + ", which do not follow one another: a vessel named by several " +
          "branches is a chain, each branch starting where the one before ends");
    last_of[name] = static_cast<int>(bi);
    vessel_of[bi] = known->second;
  }
  return vessel_of;
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
  // Lines reassembled from tracts are one per outlet by construction (two
  // centrelines may coincide at a point along a shared path).
  report->overlapping = in.tracts > 0 || overlapping(in, vertex);
  if (report->overlapping) {
    g = Graph{};
    mergeOverlapping(in, o.tolerance, &g, report);
    report->tracts = in.tracts;
    report->grouped = std::any_of(in.point_group.begin(), in.point_group.end(),
                                  [](int group) { return group >= 0; });
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
  const std::vector<int> vessel_of = branchVessels(branches, o, &c.vessel_names);
  std::vector<int> out_of(g.x.size(), -1), branch_of;
  for (size_t bi = 0; bi < branches.size(); ++bi) {
    const Branch& b = branches[bi];
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
      c.vessel.push_back(vessel_of[bi]);
      branch_of.push_back(static_cast<int>(bi));
    }
  }
  report->points = c.numPoints();
  report->branches = static_cast<int>(branches.size());
  warnCrowdedBranches(c, branch_of, branches, report);
  return c;
}

}  // namespace evsim
