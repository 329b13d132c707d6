// The graph a vessel tree is built on from a centreline file's polylines
// (internal to the geometry layer): vertices with radii and the file's
// branch ids, a grid for nearest-vertex queries, and the two ways lines
// become a graph (centerline_merge.cpp): merging layout (a)'s overlapping
// lines, or joining layout (b)'s cells. centerline_tree.cpp walks the graph
// into branches.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "endovascular_sim/geometry/centerline_tree.h"

namespace evsim {
namespace centerline_graph {

/// A point of an overlapping line within this fraction of its radius of
/// the tree built so far runs along it (layout a).
constexpr double kShared = 0.25;
/// Points closer than this coincide [m].
constexpr double kWeld = 1e-9;

inline std::string mm(const Vec3& p) {
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

inline double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b, double* t = nullptr) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  if (t) *t = s;
  return (p - (a + s * ab)).norm();
}

/// One vertex per distinct position (points within kWeld coincide); per
/// file point, its vertex.
std::vector<int> weld(const CenterlinePolylines& in, Graph* g);

/// Layout (a): no vertex is shared by two lines except as both lines' first.
bool overlapping(const CenterlinePolylines& in, const std::vector<int>& vertex);

/// Layout (a): the lines merged into g, longest first (see centerline_tree.h).
void mergeOverlapping(const CenterlinePolylines& in, double tolerance, Graph* g,
                      CenterlineTreeReport* report);

/// Layout (b): the cells joined at shared vertices.
void joinCells(const CenterlinePolylines& in, const std::vector<int>& vertex, Graph* g);

}  // namespace centerline_graph
}  // namespace evsim
