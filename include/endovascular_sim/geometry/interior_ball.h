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
// near the wall.
//
// A moving surface (vessel motion): the ball follows it. Carried by the
// displacement change at its centre, every primitive moves relative to it
// by at most kappa |y - c| (ImplicitSurface::deformationRate), which
// changes g at its points by at most a kappa + b kappa^2
// (motionSensitivity, over the box grown by kBallSlack): the ball of
// g(c) - a kappa - b kappa^2 in place of g(c) holds, while its centre has
// moved less than kBallSlack. A point deep in a lumen keeps its ball over
// many steps of a beating, breathing vessel.
#pragma once

#include <array>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/implicit_surface.h"

namespace evsim {

/// How far [m] a ball's centre may be carried by the motion before it must
/// be certified again (the sensitivity's box is grown by this much).
constexpr double kBallSlack = 5e-4;
/// Motion regions a ball records (more: it holds for one snapshot only).
constexpr int kMaxFollowedRegions = 4;

/// A ball as detection tests points against it.
struct Ball {
  Vec3 center{Vec3::Zero()};  // [m]
  double radius{-1.0};        // [m]; negative: no ball
  bool contains(const Vec3& p) const {
    return radius > 0.0 && (p - center).squaredNorm() < radius * radius;
  }
};

struct InteriorBall {
  Vec3 center{Vec3::Zero()};  // [m]
  double radius{-1.0};        // [m]; negative: no ball
  bool contains(const Vec3& p) const {
    return radius > 0.0 && (p - center).squaredNorm() < radius * radius;
  }
  // What certified it, for following the motion:
  double value{0.0}, slope{0.0}, hessian{0.0};  // g(c), |grad g(c)| [1/m], H [1/m^2]
  double reach{0.0};                            // the largest radius allowed [m]
  double max_radius{0.0};                       // the cap it was certified with [m]
  double device_radius{0.0};                    // [m]
  double a{0.0}, b{0.0};  // the motion sensitivity [-], once it was needed (sensed)
  bool sensed{false};     // a and b computed
  // The sensitivity of the ball this one replaced at the same sample point
  // (negative: none): a hint only. A ball whose value that hint uses up is
  // not followed (a point next to a moving wall, certified anew every step:
  // its own sensitivity would only confirm it). Never a ball that does not
  // hold: a ball not followed costs an evaluation, nothing else.
  double hint_a{-1.0}, hint_b{-1.0};
  bool follows{false};  // it may follow the motion (a and b exist or can be had)
  int regions{-1};      // the snapshot's regions recorded (-1: none)
  std::array<Vec3, kMaxFollowedRegions> motion{};  // the snapshot it was certified at
};

/// The certified ball around c, where `at` = surface.evaluate(c, device_radius,
/// motion) (no ball when g(c) <= 0 or the field is flat there). Its radius is
/// at most max_radius [m], the half-width of the box the Hessian bound is
/// taken over.
InteriorBall interiorBall(const ImplicitSurface& surface, const Vec3& c, const FieldSample& at,
                          double device_radius, double max_radius,
                          const MotionSnapshot& motion = {});

/// The ball as it stands at the snapshot `motion`: itself at its own
/// snapshot (or at rest); else carried and shrunk as above, or no ball
/// (radius < 0) when it cannot follow so far. The sensitivity is computed
/// the first time the ball is followed (most balls near a wall are
/// certified anew every step and never need it) and kept in *kept.
Ball followBall(InteriorBall* kept, const ImplicitSurface& surface, const MotionSnapshot& motion);

}  // namespace evsim
