// An independent check of device-pair contact: every pair of a coil's
// elements that are not neighbours, by brute force over the elements' axes
// (the activation loop finds pairs from a grid and kept candidates).
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "contact/device_pairs.h"
#include "endovascular_sim/mechanics/device_model.h"

namespace evsim::test {

/// The deepest overlap [m] of two elements of a device that are not
/// neighbours (more than 2 (r_a + r_b) plus two element lengths apart along
/// it, as device pairs count them): the sum of their radii less the distance
/// of their axes, at its largest (elements whose boxes, grown by their radii
/// and bows, do not meet are skipped). Negative when none touch.
inline double deepestSelfOverlap(const DeviceModel& m, const DeviceState& x) {
  const int ne = m.num_nodes - 1;
  std::vector<Eigen::AlignedBox3d> box(ne);
  for (int e = 0; e < ne; ++e) {
    box[e] = pairs::axisBox(m, x, e);
    box[e].min().array() -= m.node_radius[e];
    box[e].max().array() += m.node_radius[e];
  }
  double deepest = -1.0;
  for (int i = 0; i < ne; ++i)
    for (int j = i + 1; j < ne; ++j) {
      if (!box[i].intersects(box[j])) continue;
      const double r = m.node_radius[i] + m.node_radius[j];
      const double le = std::max(m.elements[i].length, m.elements[j].length);
      double xi = 0.0, xj = 0.0;
      const double d = pairs::closestAxisPoints(m, x, i, m, x, j, &xi, &xj);
      const double si = m.node_s[i] + xi * m.elements[i].length;
      const double sj = m.node_s[j] + xj * m.elements[j].length;
      if (std::abs(si - sj) <= 2.0 * r + 2.0 * le) continue;
      deepest = std::max(deepest, r - d);
    }
  return deepest;
}

}  // namespace evsim::test
