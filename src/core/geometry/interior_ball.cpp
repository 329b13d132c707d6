// Certified interior balls (geometry/interior_ball.h): the ball radius from
// g, |grad g| and a Hessian bound, used by contact detection to skip field
// evaluations of points that stay in their ball.
#include "endovascular_sim/geometry/interior_ball.h"

#include <algorithm>
#include <cmath>

namespace evsim {

InteriorBall interiorBall(const ImplicitSurface& surface, const Vec3& c, const FieldSample& at,
                          double device_radius, double max_radius) {
  InteriorBall ball;
  const double g = at.value, G = at.gradient.norm();
  if (!(g > 0.0) || !(G > 0.0) || !(max_radius > 0.0)) return ball;
  // First-order distance to the wall: no ball reaches farther, and a box of
  // that size keeps the Hessian bound local.
  const double reach = std::min(max_radius, g / G);
  const Vec3 half = Vec3::Constant(reach);
  const double H = surface.hessianBound(c - half, c + half, device_radius);
  // Smallest positive zero of g - G r - H r^2 / 2, in the form that stays
  // accurate as H -> 0.
  const double r = 2.0 * g / (G + std::sqrt(G * G + 2.0 * H * g));
  ball.center = c;
  ball.radius = std::min(r, reach);
  return ball;
}

}  // namespace evsim
