// Layouts (a) and (b) of a centreline file become a graph
// (centerline_graph.h): the overlapping lines of one polyline per outlet
// merged where they run along each other (guided by the tracts' groups
// when the lines were reassembled from vmtkbranchextractor's tracts), or
// the cells of a merged tree joined at their shared points.
#include <limits>
#include <set>

#include "centerline_graph.h"

namespace evsim {
namespace centerline_graph {
namespace {

double arcLength(const CenterlinePolylines& in, const std::vector<int>& line) {
  double s = 0.0;
  for (size_t k = 1; k < line.size(); ++k)
    s += (in.points[line[k]] - in.points[line[k - 1]]).norm();
  return s;
}

/// Where a line of layout (a) runs along the tree built so far: per point
/// from its start, the nearest tree vertex and the distance to the tree.
struct SharedStretch {
  std::vector<int> nearest;
  std::vector<double> gap;  // [m]
  int must_share{-1};       // the last point of a group the tree has (grouped lines)
  int far_by_id{0};         // points shared by their group farther than their radius
  double farthest{0.0};     // [m] the largest such distance
};

/// Layout (a): the lines merged, longest first; each line's vertices carry
/// its index in the file (its outlet), or their tract's group.
class OverlapMerger {
 public:
  OverlapMerger(const CenterlinePolylines& in, double tolerance, Graph* g)
      : in_(in), tolerance_(tolerance), g_(g), grid_(gridSize(in)) {}

  void merge(CenterlineTreeReport* report) {
    std::vector<int> order;
    for (size_t l = 0; l < in_.lines.size(); ++l)
      if (in_.lines[l].size() >= 2) order.push_back(static_cast<int>(l));
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return arcLength(in_, in_.lines[a]) > arcLength(in_, in_.lines[b]);
    });
    append(order[0], 0, -1);
    for (size_t o = 1; o < order.size(); ++o) {
      const std::vector<int>& line = in_.lines[order[o]];
      const SharedStretch s = alongTheTree(line);
      if (s.far_by_id > 0) {
        std::ostringstream w;
        w << "centreline " << order[o] << ": " << s.far_by_id
          << " points of groups already in the tree lie up to " << s.farthest * 1e3
          << " mm from it, beyond their radius; merged by their group ids";
        report->warnings.push_back(w.str());
      }
      if (s.nearest.size() == line.size()) continue;  // wholly along the tree
      if (s.nearest.empty())
        throw std::invalid_argument("line " + std::to_string(order[o]) +
                                    " does not start on the others (layout of one line per "
                                    "outlet, each from the inlet)");
      // The line separates gradually: it branches where its distance to the
      // tree last was that of the shared stretch (twice its median, plus the
      // tolerance), not where it leaves the tube; never before the last
      // point of a group the tree has.
      std::vector<double> sorted = s.gap;
      std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
      const double shared = 2.0 * sorted[sorted.size() / 2] + tolerance_;
      int j = static_cast<int>(s.gap.size()) - 1;
      while (j > std::max(0, s.must_share) && s.gap[j] > shared) --j;
      append(order[o], j + 1, s.nearest[j]);
    }
  }

 private:
  static double gridSize(const CenterlinePolylines& in) {
    const double r_max = *std::max_element(in.radius.begin(), in.radius.end());
    return std::max(kShared * r_max, 1e-5);
  }
  int groupOf(int p) const { return in_.point_group.empty() ? -1 : in_.point_group[p]; }

  void append(int line, size_t from, int attach) {
    int prev = attach;
    for (size_t k = from; k < in_.lines[line].size(); ++k) {
      const int p = in_.lines[line][k];
      const int v =
          g_->add(in_.points[p], in_.radius[p], in_.point_group.empty() ? line : groupOf(p));
      grid_.insert(in_.points[p], v);
      if (groupOf(p) >= 0) tree_groups_.insert(groupOf(p));
      if (prev >= 0) g_->join(prev, v);
      prev = v;
    }
  }

  /// The tree's vertex nearest p within the grid's reach (-1: none), and
  /// the distance to the tree's edges there.
  int nearestOnTree(const Vec3& p, double* best) const {
    *best = std::numeric_limits<double>::infinity();
    int closest = -1;
    grid_.near(p, [&](int v) {
      double d = (g_->x[v] - p).norm();
      for (int w : g_->adj[v]) d = std::min(d, segmentDistance(p, g_->x[v], g_->x[w]));
      if (d < *best) *best = d, closest = v;
    });
    return closest;
  }

  /// The nearest vertex of a group, searched through the whole tree.
  int nearestOfGroup(const Vec3& p, int group, double* best) const {
    *best = std::numeric_limits<double>::infinity();
    int closest = -1;
    for (size_t v = 0; v < g_->x.size(); ++v)
      if (g_->id[v] == group && (g_->x[v] - p).norm() < *best)
        *best = (g_->x[v] - p).norm(), closest = static_cast<int>(v);
    return closest;
  }

  /// A point of a group in the tree is shared, whatever its distance; a
  /// point of a new group branches; other points (no groups, blanked
  /// tracts) are shared while within kShared of their radius of the tree.
  SharedStretch alongTheTree(const std::vector<int>& line) const {
    SharedStretch s;
    for (size_t k = 0; k < line.size(); ++k) {
      const int p = line[k];
      const int group = groupOf(p);
      const bool known = group >= 0 && tree_groups_.count(group);
      if (group >= 0 && !known) break;
      double best;
      int closest = nearestOnTree(in_.points[p], &best);
      if (known) {
        if (closest < 0) closest = nearestOfGroup(in_.points[p], group, &best);
        s.must_share = static_cast<int>(k);
        if (best > in_.radius[p]) ++s.far_by_id, s.farthest = std::max(s.farthest, best);
      } else if (best > kShared * in_.radius[p]) {
        break;
      }
      s.nearest.push_back(closest);
      s.gap.push_back(best);
    }
    return s;
  }

  const CenterlinePolylines& in_;
  double tolerance_;
  Graph* g_;
  VertexGrid grid_;
  std::set<int> tree_groups_;  // the groups of the vertices appended so far
};

}  // namespace

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

void mergeOverlapping(const CenterlinePolylines& in, double tolerance, Graph* g,
                      CenterlineTreeReport* report) {
  OverlapMerger(in, tolerance, g).merge(report);
}

void joinCells(const CenterlinePolylines& in, const std::vector<int>& vertex, Graph* g) {
  for (const auto& line : in.lines)
    for (size_t k = 1; k < line.size(); ++k) g->join(vertex[line[k - 1]], vertex[line[k]]);
}

}  // namespace centerline_graph
}  // namespace evsim
