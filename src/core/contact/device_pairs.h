// Pairs of device sample points closer than the sum of their radii (the
// effect 'device_contact'; internal to the contact solver,
// contact_solver.cpp).
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"

namespace evsim {
namespace pairs {

/// A sample point in a configuration (held ones are kinematic obstacles).
struct PointRef {
  bool free;
  int device, sample, element;
  double s;         // material coordinate [m]
  Vec3 p;           // [m]
  double r;         // [m]
  int in_lumen_of;  // effect 'coaxial': the outer device whose lumen holds it (-1: none)
  int body{0};      // 1: the part of its device cut off by a detachment (a coil), else 0
};

struct Pair {
  int a, b;  // indices into the point list
  double distance;
};

/// Normal of a contact between two device points, from b to a (axis
/// tangents ta, tb); see device_pairs.cpp.
Vec3 pairNormal(const Vec3& pa, const Vec3& ta, const Vec3& pb, const Vec3& tb);

/// Pairs of points, at least one of them free, closer than the sum of their
/// radii plus `margin` [m]; see device_pairs.cpp.
std::vector<Pair> findPairs(const std::vector<DeviceModel>& devices,
                            const std::vector<PointRef>& pts, double margin);

}  // namespace pairs
}  // namespace evsim
