// Where a ray runs inside simple solids: the exact intervals the X-ray
// projection integrates over (devices as cylinders, the body as an
// elliptic cylinder, the vessels' bounding capsules).
#pragma once

#include "endovascular_sim/core/types.h"

namespace evsim {

/// Ray parameters [t0, t1] (t: distance along a unit direction [m]);
/// empty when t1 <= t0.
struct RayInterval {
  double t0{0.0}, t1{0.0};
  bool empty() const { return !(t1 > t0); }
  double length() const { return empty() ? 0.0 : t1 - t0; }
};

/// The ray o + t d (d unit) inside the cylinder of radius r around the
/// axis a + s u (u unit), cut to s in [s0, s1] (flat caps).
RayInterval rayInCylinder(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& u, double r,
                          double s0, double s1);

/// The ray inside the infinite elliptic cylinder around the axis through
/// c along `axis` (unit), of semi-axes ea along e (unit, perpendicular to
/// the axis) and eb along axis x e.
RayInterval rayInEllipticCylinder(const Vec3& o, const Vec3& d, const Vec3& c, const Vec3& axis,
                                  const Vec3& e, double ea, double eb);

}  // namespace evsim
