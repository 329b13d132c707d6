// Collision detection on the implicit surface (section 2.3 of the paper).
//
// firstRoot finds the first point where g = f - T changes from >= 0 (inside)
// to < 0 on the segment [P_t, P_t+1]: a modified Newton-Raphson whose steps
// are certified. With H a bound of |g''| along the segment (from the Hessian
// bounds of the primitives near it), g(s + d) >= g(s) + g'(s) d - H d^2 / 2,
// so the step d to the first zero of that lower bound never passes a root —
// a thin wall cannot be jumped — while near a simple root it behaves like
// Newton's step (quadratic convergence). The root is finished by bisection.
// Only penetrations deeper than eps (crossing_depth) count (Signorini's gap >=
// -tolerance): the certified steps run on g + eps |grad f|, which keeps them
// long (micrometres) for a point sliding along the wall, where steps on g
// alone would shrink like sqrt(g). The reported root is still the exact zero
// of g between the last inside and the first outside point.
//
// projectToSurface is the paper's update of a contact for a corrected
// position x: from x along the gradient, i = x + nu grad g / |grad g|, to the
// surface; it returns the new point and normal (the new tangent plane).
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/implicit_surface.h"

namespace evsim {

struct RootOptions {
  double tolerance{1e-11};      // on the root's position [m]
  double crossing_depth{1e-9};  // a crossing shallower than this is not a hit [m]
  int max_iterations{1000};     // certified steps before giving up
};

struct SurfacePoint {
  bool hit{false};              // a crossing (or an outside start) was found
  bool started_outside{false};  // g(P_t) < 0 already
  double s{1.0};                // fraction of [P_t, P_t+1] at the root
  Vec3 point{Vec3::Zero()};     // on the surface [m]
  Vec3 normal{Vec3::Zero()};    // unit, into the lumen
  int iterations{0};
};

SurfacePoint firstRoot(const ImplicitSurface& field, const Vec3& p0, const Vec3& p1,
                       double device_radius, const MotionSnapshot& motion = {},
                       const RootOptions& options = {});

/// firstRoot with the field at p0 already evaluated (at = evaluate(p0)): a
/// point's later motions from the same start (the activation loop's
/// re-detection along x_t -> x) cost no evaluation where the Hessian bound
/// certifies the whole path inside.
SurfacePoint firstRootFrom(const ImplicitSurface& field, const Vec3& p0, const FieldSample& at,
                           const Vec3& p1, double device_radius, const MotionSnapshot& motion = {},
                           const RootOptions& options = {});

/// firstRootFrom with the field at p1 known too (at_end = evaluate(p1)): the
/// path is certified from both ends (a point near the wall whose short
/// path ends inside costs no evaluation where the bounds from its two ends
/// meet). The same answer as firstRootFrom.
SurfacePoint firstRootBetween(const ImplicitSurface& field, const Vec3& p0, const FieldSample& at,
                              const Vec3& p1, const FieldSample& at_end, double device_radius,
                              const MotionSnapshot& motion = {}, const RootOptions& options = {});

/// Surface point reached from x along the gradient direction at x, and its
/// normal. hit is false when no surface lies within max_distance [m].
SurfacePoint projectToSurface(const ImplicitSurface& field, const Vec3& x, double device_radius,
                              const MotionSnapshot& motion = {}, double max_distance = 0.01,
                              const RootOptions& options = {});
/// projectToSurface with the field at x already evaluated (at = evaluate(x)).
SurfacePoint projectToSurfaceFrom(const ImplicitSurface& field, const Vec3& x,
                                  const FieldSample& at, double device_radius,
                                  const MotionSnapshot& motion = {}, double max_distance = 0.01,
                                  const RootOptions& options = {});

}  // namespace evsim
