// Certified interior balls: where the surface proves a point cannot touch
// the wall, detection needs no field evaluation.
//
// From one evaluation at c (g > 0, gradient G = |grad g|) and a bound H of
// the Hessian's norm over a box around c, Taylor's theorem gives
//   g(p) >= g(c) - G |p - c| - H |p - c|^2 / 2,
// positive for |p - c| < r = 2 g / (G + sqrt(G^2 + 2 H g)). Every point of
// that ball lies strictly inside the free space, and so does every segment
// between two of its points (the ball is convex): a sample point whose
// motion stays in its ball has no first root, is not violated and did not
// tunnel. A device at rest, or sliding slowly through a lumen, keeps its
// points in their balls for many steps, and the field is evaluated only
// near the wall. Valid while the surface does not move.
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/implicit_surface.h"

namespace evsim {

struct InteriorBall {
  Vec3 center{Vec3::Zero()};  // [m]
  double radius{-1.0};        // [m]; negative: no ball
  bool contains(const Vec3& p) const {
    return radius > 0.0 && (p - center).squaredNorm() < radius * radius;
  }
};

/// The certified ball around c, where `at` = surface.evaluate(c, device_radius)
/// (no ball when g(c) <= 0 or the field is flat there). Its radius is at most
/// max_radius [m], the half-width of the box the Hessian bound is taken over.
InteriorBall interiorBall(const ImplicitSurface& surface, const Vec3& c, const FieldSample& at,
                          double device_radius, double max_radius);

}  // namespace evsim
