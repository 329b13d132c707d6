// How closely the convolution surface reproduces a centreline's radii.
// Declared and documented in endovascular_sim/geometry/surface_fidelity.h.
#include "endovascular_sim/geometry/surface_fidelity.h"

#include <algorithm>
#include <cmath>

#include "endovascular_sim/geometry/root_finding.h"

namespace evsim {
namespace {

FidelityFigures summarize(std::vector<double> errors) {
  FidelityFigures f;
  f.rays = static_cast<int>(errors.size());
  if (errors.empty()) return f;
  std::sort(errors.begin(), errors.end());
  f.median = errors[errors.size() / 2];
  f.worst = errors.back();
  return f;
}

}  // namespace

SurfaceFidelity measureSurfaceFidelity(const ImplicitSurface& surface, const Centerline& c) {
  const int n = c.numPoints();
  std::vector<int> degree(n, 0);
  for (int i = 0; i < n; ++i)
    if (c.parent[i] >= 0) ++degree[i], ++degree[c.parent[i]];
  std::vector<int> special;  // junctions and ends
  for (int i = 0; i < n; ++i)
    if (degree[i] != 2) special.push_back(i);
  std::vector<double> along, at_forks;
  for (int i = 0; i < n; ++i) {
    const int j = c.parent[i];
    if (j < 0) continue;
    const Vec3 axis = c.position[i] - c.position[j];
    if (axis.norm() <= 0.0) continue;
    const Vec3 p = 0.5 * (c.position[i] + c.position[j]);
    const double r = 0.5 * (c.radius[i] + c.radius[j]);
    bool near = false;
    for (int s : special)
      near = near || (c.position[s] - p).norm() < 2.0 * std::max(r, c.radius[s]);
    // Another vessel's lumen within a radius of this wall: the lumens blend.
    for (int a = 0; a < n && !near; ++a) {
      const int b = c.parent[a];
      if (b < 0 || a == i || a == j || b == i || b == j) continue;
      const Vec3 ab = c.position[a] - c.position[b];
      const double t = ab.squaredNorm() > 0.0
                           ? std::clamp((p - c.position[b]).dot(ab) / ab.squaredNorm(), 0.0, 1.0)
                           : 0.0;
      const double reach = 2.0 * r + std::max(c.radius[a], c.radius[b]);
      near = (p - (c.position[b] + t * ab)).norm() < reach &&
             c.vessel[a] != c.vessel[i];  // the own vessel's bends are measured
    }
    const Vec3 u = axis.normalized();
    for (int k = 0; k < 4; ++k) {
      const Vec3 out = Eigen::AngleAxisd(k * M_PI / 2.0, u) * u.unitOrthogonal();
      const SurfacePoint w = firstRoot(surface, p, p + 3.0 * r * out, 0.0);
      const double lumen = w.hit ? (w.point - p).norm() : 3.0 * r;
      (near ? at_forks : along).push_back(std::abs(lumen / r - 1.0));
    }
  }
  return {summarize(along), summarize(at_forks)};
}

}  // namespace evsim
