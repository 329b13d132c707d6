// A deterministic generator of large vascular networks.
//
// Constrained recursive bifurcation, grown breadth-first from the leaves of a
// given centreline (e.g. the carotid path) until a target vessel count:
//  - radii by Murray's law, r_p^3 = r_1^3 + r_2^3, with a random asymmetry
//    r_2 / r_1 in [0.6, 1];
//  - branching angles from Murray's optimum, cos(theta_1) = (r_p^4 + r_1^4 -
//    r_2^4) / (2 r_p^2 r_1^2), the bifurcation plane turned by 90 +- 30 deg
//    per generation to fill space;
//  - vessel length lambda r with lambda in [8, 16], as two segments, gently
//    curved;
//  - a candidate vessel is rejected (and retried with other angles, up to 8
//    times) when it comes closer than the sum of radii to a vessel that is
//    not its parent or sibling, or leaves the growth box; vessels thinner
//    than min_radius are not split further.
// The random numbers come from std::mt19937_64 mapped to [0, 1) by hand, so
// the network is the same on every platform for a seed.
#pragma once

#include <cstdint>

#include "endovascular_sim/geometry/centerline.h"

namespace evsim {

struct NetworkOptions {
  uint64_t seed{7};
  int vessels{4000};           // target number of generated vessels
  double min_radius{0.15e-3};  // [m]
  Eigen::AlignedBox3d growth_box{Vec3(-0.12, -0.08, 0.15), Vec3(0.12, 0.12, 0.32)};  // [m]
  int only_type{-1};  // grow only from leaves of this SWC type (-1: all)
};

/// Adds the generated network to `base` (its leaves are the roots of the
/// growth). Generated points get SWC type 7; a generated vessel is named
/// after its parent with "_1" (the larger daughter) or "_2" appended. Returns the number of vessels
/// added.
int growNetwork(const NetworkOptions& options, Centerline* base);

}  // namespace evsim
