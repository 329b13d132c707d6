// Certified interior balls (geometry/interior_ball.h): the ball radius from
// g, |grad g| and a Hessian bound, used by contact detection to skip field
// evaluations of points that stay in their ball.
#include "endovascular_sim/geometry/interior_ball.h"

#include <algorithm>
#include <cmath>

#include "endovascular_sim/core/thread_cache.h"

namespace evsim {

InteriorBall interiorBall(const ImplicitSurface& surface, const Vec3& c, const FieldSample& at,
                          double device_radius, double max_radius, const MotionSnapshot& motion) {
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
  if (motion.empty()) return ball;
  ball.value = g;
  ball.slope = G;
  ball.hessian = H;
  ball.reach = reach;
  ball.max_radius = max_radius;
  ball.device_radius = device_radius;
  // A wall that gives way changes shape every step: its balls hold for
  // one snapshot only.
  if (!motion.wall && static_cast<int>(motion.regions.size()) <= kMaxFollowedRegions) {
    ball.regions = static_cast<int>(motion.regions.size());
    std::copy(motion.regions.begin(), motion.regions.end(), ball.motion.begin());
    ball.follows = true;
  }
  return ball;
}

Ball followBall(InteriorBall* kept, const ImplicitSurface& surface, const MotionSnapshot& motion) {
  const InteriorBall& ball = *kept;
  const Ball as_certified{ball.center, ball.radius};
  if (ball.radius <= 0.0 || motion.empty()) return as_certified;
  if (motion.wall || ball.regions != static_cast<int>(motion.regions.size()) || !ball.follows)
    return Ball{};
  const std::vector<Vec3>& regions = motion.regions;
  if (std::equal(regions.begin(), regions.end(), ball.motion.begin())) return as_certified;
  // The balls certified at one snapshot share kappa: kept for the last one.
  struct LastKappa {
    std::vector<Vec3> then, now;
    double kappa{0.0};
  };
  LastKappa& last = threadCache<LastKappa>();
  if (last.now != regions || !std::equal(last.then.begin(), last.then.end(), ball.motion.begin()) ||
      static_cast<int>(last.then.size()) != ball.regions) {
    last.then.assign(ball.motion.begin(), ball.motion.begin() + ball.regions);
    last.now = regions;
    last.kappa = surface.deformationRate(last.then, regions);
  }
  if (!ball.sensed && ball.hint_a >= 0.0 &&
      ball.value <= ball.hint_a * last.kappa + ball.hint_b * last.kappa * last.kappa)
    return Ball{};  // (InteriorBall::hint_a)
  const Vec3 shift = surface.displacementChange(ball.center, last.then, regions);
  if (shift.squaredNorm() > kBallSlack * kBallSlack) return Ball{};
  if (!ball.sensed) {
    // (over the cap's box, not the ball's: one box for every ball, which a
    // surface may keep per region)
    kept->follows = surface.motionSensitivity(ball.center, ball.max_radius + kBallSlack,
                                              ball.device_radius, &kept->a, &kept->b);
    kept->sensed = true;
    if (!ball.follows) return Ball{};
  }
  const double kappa = last.kappa;
  const double g = ball.value - ball.a * kappa - ball.b * kappa * kappa;
  if (!(g > 0.0)) return Ball{};
  const double G = ball.slope, H = ball.hessian;
  return Ball{ball.center + shift,
              std::min(2.0 * g / (G + std::sqrt(G * G + 2.0 * H * g)), ball.reach)};
}

}  // namespace evsim
