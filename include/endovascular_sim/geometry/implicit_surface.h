// What contact detection needs of a surface: g (> 0 inside the free space,
// < 0 beyond the wall), its gradient, and a bound of its Hessian. The vessel
// field is one; a plane is another (tests, simple scenes).
#pragma once

#include <memory>
#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/kernel.h"

namespace evsim {

/// The shape of a vessel wall that gives way (geometry/vessel_wall.h) at
/// one moment: each centreline point's displacement and radius change.
struct WallShape {
  long version{0};                    // unique per shape: what snapshots compare
  std::vector<Vec3> displacement;     // per centreline point [m]
  std::vector<double> radius_change;  // per centreline point [m]
};

/// The vessels at one time: the displacement of every motion region and,
/// when the wall gives way, its shape (both empty: at rest).
struct MotionSnapshot {
  std::vector<Vec3> regions;              // [m]
  std::shared_ptr<const WallShape> wall;  // null: the wall at rest
  bool empty() const { return regions.empty() && !wall; }
  bool operator==(const MotionSnapshot& o) const {
    return regions == o.regions && (wall ? wall->version : -1) == (o.wall ? o.wall->version : -1);
  }
  bool operator!=(const MotionSnapshot& o) const { return !(*this == o); }
};

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

  // What a certified ball needs to follow a moving surface
  // (geometry/interior_ball.h); a surface that cannot say keeps the
  // defaults, and its balls hold for one snapshot only.
  /// The change of the motion regions' displacement at x from the regions
  /// of one snapshot, m0, to those of another, m1 [m].
  virtual Vec3 displacementChange(const Vec3& /*x*/, const std::vector<Vec3>& /*m0*/,
                                  const std::vector<Vec3>& /*m1*/) const {
    return Vec3::Zero();
  }
  /// kappa [-]: every point y of the surface's primitives moves, from m0 to
  /// m1, relative to the displacement change at any x, by at most kappa |y -
  /// x| (y at rest).
  virtual double deformationRate(const std::vector<Vec3>& /*m0*/,
                                 const std::vector<Vec3>& /*m1*/) const {
    return 0.0;
  }
  /// a, b [-]: when every primitive point y moves by at most kappa |y - c|
  /// relative to a frame, g at every point q within half_width [m] of c
  /// changes (q fixed in that frame) by at most a kappa + b kappa^2. False
  /// when the surface gives no such bound.
  virtual bool motionSensitivity(const Vec3& /*c*/, double /*half_width*/, double /*device_radius*/,
                                 double* /*a*/, double* /*b*/) const {
    return false;
  }
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
