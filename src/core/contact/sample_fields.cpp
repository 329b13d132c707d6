// Lazily evaluated fields of the sample points, spared inside certified
// balls (contact/sample_fields.h); part of the contact solver's detection.
#include "sample_fields.h"

namespace evsim {
namespace fields {

SampleFields::SampleFields(const ImplicitSurface* surface, const std::vector<size_t>& counts,
                           std::vector<std::vector<InteriorBall>>* balls,
                           const MotionSnapshot* motion)
    : surface_(surface), balls_(balls), motion_(motion && !motion->empty() ? motion : nullptr) {
  const size_t nd = counts.size();
  start_ball_.resize(nd);
  start_.resize(nd);
  end_.resize(nd);
  start_at_.resize(nd);
  end_at_.resize(nd);
  start_known_.resize(nd);
  end_known_.resize(nd);
  if (balls_) balls_->resize(nd);
  for (size_t d = 0; d < nd; ++d) {
    start_ball_[d].assign(counts[d], Ball{});
    start_[d].resize(counts[d]);
    end_[d].resize(counts[d]);
    start_at_[d].resize(counts[d]);
    end_at_[d].resize(counts[d]);
    start_known_[d].assign(counts[d], 0);
    end_known_[d].assign(counts[d], 0);
    if (balls_ && (*balls_)[d].size() != counts[d]) (*balls_)[d].assign(counts[d], InteriorBall{});
  }
  if (balls_ && motion_) {
    now_.resize(nd);
    now_known_.resize(nd);
    for (size_t d = 0; d < nd; ++d) {
      now_[d].resize(counts[d]);
      now_known_[d].assign(counts[d], 0);
    }
  }
}

void SampleFields::recentre(int d, int k, const Vec3& c, const FieldSample& at, double radius) {
  if (!balls_) return;
  InteriorBall& ball = (*balls_)[d][k];
  const double hint_a = ball.sensed ? ball.a : ball.hint_a;
  const double hint_b = ball.sensed ? ball.b : ball.hint_b;
  ball =
      interiorBall(*surface_, c, at, radius, kMaxBallRadius, motion_ ? *motion_ : MotionSnapshot{});
  ball.hint_a = hint_a;
  ball.hint_b = hint_b;
  if (motion_) {  // certified at this snapshot: as it stands
    now_[d][k] = Ball{(*balls_)[d][k].center, (*balls_)[d][k].radius};
    now_known_[d][k] = 1;
  }
}

bool SampleFields::ballContains(int d, int k, const Vec3& p) {
  if (motion_ && !now_known_[d][k]) {
    // The kept ball followed to this snapshot is no larger than as
    // certified, and its centre moved by at most kBallSlack (else none):
    // a point farther than both from the centre is outside it, known
    // without following (or the sensitivity that following needs).
    const InteriorBall& kept = (*balls_)[d][k];
    const double beyond = kept.radius + kBallSlack + 1e-9;
    if (!(kept.radius > 0.0) || (p - kept.center).squaredNorm() >= beyond * beyond) return false;
  }
  return ball(d, k).contains(p);
}

Ball SampleFields::ball(int d, int k) {
  if (!motion_) return Ball{(*balls_)[d][k].center, (*balls_)[d][k].radius};
  if (!now_known_[d][k]) {
    now_[d][k] = followBall(&(*balls_)[d][k], *surface_, *motion_);
    now_known_[d][k] = 1;
  }
  return now_[d][k];
}

bool SampleFields::startInside(int d, int k, const Vec3& p0, const Vec3& p1, double radius,
                               const MotionSnapshot& motion) {
  if (balls_ && ballContains(d, k, p0) && ballContains(d, k, p1)) {
    start_ball_[d][k] = ball(d, k);
    return true;
  }
  const FieldSample& g0 = start(d, k, p0, radius, motion);
  if (!balls_) return false;
  recentre(d, k, p0, g0, radius);
  start_ball_[d][k] = ball(d, k);
  return start_ball_[d][k].contains(p1);
}

bool SampleFields::endWithinTolerance(int d, int k, const Vec3& p, double radius,
                                      const MotionSnapshot& motion, double tolerance,
                                      double* depth_bound) {
  *depth_bound = 0.0;
  if (balls_ && ballContains(d, k, p)) return true;
  const bool have_end = end_known_[d][k] != 0;
  if (have_end || start_known_[d][k]) {  // the field at the point's last place this step
    const FieldSample& last = have_end ? end_[d][k] : start_[d][k];
    const Vec3& at = have_end ? end_at_[d][k] : start_at_[d][k];
    const Vec3 step = p - at;
    const double length = step.norm();
    if (length > 0.0) {
      const double H = surface_->hessianBound(at, p, radius);
      const double g = last.value + last.gradient.dot(step) - 0.5 * H * length * length;
      const double slope = last.gradient.norm() - H * length;
      if (g >= 0.0) return true;
      if (slope > 0.0 && -g <= tolerance * slope) {
        *depth_bound = -g / slope;
        return true;
      }
    }
  }
  const FieldSample& g = end(d, k, p, radius, motion);
  if (balls_ && g.value > 0.0) recentre(d, k, p, g, radius);
  return false;
}

bool SampleFields::chordInside(int d, int k, const Vec3& p0, const Vec3& p) {
  if (start_ball_[d][k].contains(p)) return true;  // it holds p0 whenever it exists
  return balls_ && ballContains(d, k, p0) && ballContains(d, k, p);
}

const FieldSample& SampleFields::start(int d, int k, const Vec3& p0, double radius,
                                       const MotionSnapshot& motion) {
  if (!start_known_[d][k]) {
    start_[d][k] = surface_->evaluate(p0, radius, motion);
    start_at_[d][k] = p0;
    start_known_[d][k] = 1;
  }
  return start_[d][k];
}

const FieldSample& SampleFields::end(int d, int k, const Vec3& p, double radius,
                                     const MotionSnapshot& motion) {
  if (!end_known_[d][k] || end_at_[d][k] != p) {
    end_[d][k] = surface_->evaluate(p, radius, motion);
    end_at_[d][k] = p;
    end_known_[d][k] = 1;
  }
  return end_[d][k];
}

}  // namespace fields
}  // namespace evsim
