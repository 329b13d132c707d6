// What contact detection needs of a surface: g (> 0 inside the free space,
// < 0 beyond the wall), its gradient, and a bound of its Hessian. The vessel
// field is one; a plane is another (tests, simple scenes).
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/kernel.h"

namespace evsim {

/// Displacement of every motion region at one time (empty: at rest).
using MotionSnapshot = std::vector<Vec3>;

class ImplicitSurface {
 public:
  virtual ~ImplicitSurface() = default;
  /// g and grad g at p, for a device of radius r [m] (the surface is offset
  /// by r).
  virtual FieldSample evaluate(const Vec3& p, double device_radius,
                               const MotionSnapshot& motion = {}) const = 0;
  /// Bound of |Hessian of g| [1/m^2] over the box of [p0, p1].
  virtual double hessianBound(const Vec3& p0, const Vec3& p1, double device_radius) const = 0;
  /// Region displacements at time t (empty when nothing moves).
  virtual MotionSnapshot motionAt(double /*t*/) const { return {}; }
};

/// The half-space n . (p - origin) >= 0 (n unit, pointing into the free
/// space); g is the signed distance minus the device radius [m].
class PlaneSurface : public ImplicitSurface {
 public:
  PlaneSurface(const Vec3& origin, const Vec3& normal) : origin_(origin), n_(normal.normalized()) {}
  FieldSample evaluate(const Vec3& p, double r, const MotionSnapshot& = {}) const override {
    FieldSample s;
    s.value = n_.dot(p - origin_) - r;
    s.gradient = n_;
    return s;
  }
  double hessianBound(const Vec3&, const Vec3&, double) const override { return 0.0; }

 private:
  Vec3 origin_, n_;
};

}  // namespace evsim
