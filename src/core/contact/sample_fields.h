// The field at each sample point's start x_t and at the activation loop's
// x, evaluated only where detection cannot do without it (internal to the
// contact solver, contact_solver.cpp). A point whose motion stays in its
// certified interior ball (geometry/interior_ball.h) is inside throughout:
// no first root, no violation, no tunnel, and no evaluation. The balls are
// kept across steps (SimData); on a moving surface each follows the motion
// from the snapshot it was certified at (followBall), as far as it can.
#pragma once

#include <vector>

#include "endovascular_sim/geometry/implicit_surface.h"
#include "endovascular_sim/geometry/interior_ball.h"

namespace evsim {
namespace fields {

/// Largest certified ball [m]: its Hessian bound is taken over a box of
/// twice this size, so a larger one is looser everywhere.
constexpr double kMaxBallRadius = 2e-3;

class SampleFields {
 public:
  /// counts: sample points per device. balls: where the balls are kept
  /// (resized to the counts), or null (the option off: every point is
  /// evaluated).
  SampleFields(const ImplicitSurface* surface, const std::vector<size_t>& counts,
               std::vector<std::vector<InteriorBall>>* balls, const MotionSnapshot* motion);

  /// True when the path p0 -> p1 of point (d, k) is certified inside; else
  /// its field at p0 is evaluated (and its ball re-centred there) and false.
  bool startInside(int d, int k, const Vec3& p0, const Vec3& p1, double radius,
                   const MotionSnapshot& motion);
  /// True when p (the loop's x) is certified to lie at most `tolerance`
  /// beyond the wall, *depth_bound then bounding its depth [m] (0 inside):
  /// by its ball, or by Taylor's bounds from the point's last evaluation in
  /// this step (g >= g_l + grad g_l . dp - H |dp|^2 / 2, |grad g| >= |grad g_l|
  /// - H |dp|: a point pressed on the wall that moved a few micrometres
  /// since the last loop). Else its field at p is evaluated (and its ball
  /// re-centred there when inside) and false.
  bool endWithinTolerance(int d, int k, const Vec3& p, double radius, const MotionSnapshot& motion,
                          double tolerance, double* depth_bound);
  /// True when the chord p0 -> p lies in a certified ball (no tunnel).
  bool chordInside(int d, int k, const Vec3& p0, const Vec3& p);

  /// The field at p0 (x_t), evaluated once a step; at p (the point's place
  /// in an iterate), evaluated unless the last evaluation was at p.
  const FieldSample& start(int d, int k, const Vec3& p0, double radius,
                           const MotionSnapshot& motion);
  const FieldSample& end(int d, int k, const Vec3& p, double radius, const MotionSnapshot& motion);

 private:
  /// Re-centres (d, k)'s ball at c, where the field is `at`.
  void recentre(int d, int k, const Vec3& c, const FieldSample& at, double radius);
  /// (d, k)'s ball at this step's snapshot (its kept ball followed there).
  Ball ball(int d, int k);
  /// ball(d, k).contains(p), without following the ball where p is too far
  /// from it to be contained however it follows.
  bool ballContains(int d, int k, const Vec3& p);

  const ImplicitSurface* surface_;
  std::vector<std::vector<InteriorBall>>* balls_;  // as certified
  const MotionSnapshot* motion_;                   // this step's (null or empty: at rest)
  std::vector<std::vector<Ball>> now_;             // moving: balls_ followed to motion_
  std::vector<std::vector<char>> now_known_;
  std::vector<std::vector<Ball>> start_ball_;  // the ball x_t lay in
  std::vector<std::vector<FieldSample>> start_, end_;
  std::vector<std::vector<Vec3>> start_at_, end_at_;  // where start_, end_ were evaluated
  std::vector<std::vector<char>> start_known_, end_known_;
};

}  // namespace fields
}  // namespace evsim
