// Certified interior balls (geometry/interior_ball.h) and the detection that
// skips evaluations in them (contact/sample_fields.h): the ball against the
// exact distance to a plane, every point of a ball inside the vessels (also
// of a ball following the vessels' motion, against fresh evaluations), and a
// whole scene stepped with and without the balls to the same last bit.
#include "endovascular_sim/geometry/interior_ball.h"

#include <gtest/gtest.h>

#include <random>

#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

TEST(InteriorBall, ReachesTheWallOfAPlaneExactly) {
  // g is the signed distance minus the radius, its Hessian zero: the ball
  // is the largest one free of the wall (up to the cap).
  const PlaneSurface plane(Vec3::Zero(), Vec3(0.0, 0.0, 1.0));
  const Vec3 c(0.001, -0.002, 0.0015);
  const InteriorBall ball = interiorBall(plane, c, plane.evaluate(c, 2e-4), 2e-4, 0.01);
  EXPECT_NEAR(ball.radius, 0.0015 - 2e-4, 1e-15);
  EXPECT_EQ(interiorBall(plane, c, plane.evaluate(c, 2e-4), 2e-4, 5e-4).radius, 5e-4);  // the cap
  const Vec3 beyond(0.0, 0.0, 1e-4);  // beyond the offset wall: no ball
  EXPECT_LT(interiorBall(plane, beyond, plane.evaluate(beyond, 2e-4), 2e-4, 0.01).radius, 0.0);
}

TEST(InteriorBall, EveryPointOfABallInTheCarotidIsInside) {
  const SceneSpec spec = loadSceneFile(resolveScenePath("carotid"));
  const VesselField field = buildVesselField(spec.vessels, false);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::AlignedBox3d box = field.bounds();
  int balls = 0, probes = 0;
  double largest = 0.0;
  while (balls < 400) {
    const Vec3 c =
        box.min() + (0.5 * (Vec3(u(rng), u(rng), u(rng)) + Vec3::Ones())).cwiseProduct(box.sizes());
    const double r = 1.8e-4;  // the guidewire's radius
    const FieldSample at = field.evaluate(c, r);
    if (at.value <= 0.0) continue;
    const InteriorBall ball = interiorBall(field, c, at, r, 2e-3);
    ASSERT_GT(ball.radius, 0.0);
    ++balls;
    largest = std::max(largest, ball.radius);
    for (int k = 0; k < 50; ++k, ++probes) {  // on its sphere and inside
      const Vec3 p =
          c + ball.radius * std::abs(u(rng)) * 0.999999 * Vec3(u(rng), u(rng), u(rng)).normalized();
      ASSERT_GT(field.evaluate(p, r).value, 0.0) << "ball " << balls << " probe " << k;
    }
  }
  std::printf("[ metric   ] interior balls: %d balls, %d probes inside, largest %.3g mm\n", balls,
              probes, largest * 1e3);
  EXPECT_GT(largest, 5e-4);  // balls are not vanishingly small
}

TEST(InteriorBall, ABallFollowingTheNetworksMotionHoldsOnlyInsidePoints) {
  // Balls certified in the beating, breathing network at t0 and followed
  // to t0 + 1 ms ... 0.4 s (followBall): every probe of a followed ball is
  // inside at t1, evaluated afresh there; and the field's change at a ball's
  // points, carried with its centre, stays under the sensitivity's bound.
  const SceneSpec spec = loadSceneFile(resolveScenePath("network"));
  const VesselField field = buildVesselField(spec.vessels, true);
  ASSERT_TRUE(field.moves());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::AlignedBox3d box = field.bounds();
  const double r = 1.8e-4;  // the guidewire's radius
  const double kDelays[] = {1e-3, 5e-3, 2e-2, 1e-1, 4e-1};
  int certified = 0, followed[5] = {0, 0, 0, 0, 0}, probes = 0;
  double tightest = 0.0;  // largest change over its bound
  for (int tries = 0; certified < 300 && tries < 2000000; ++tries) {
    const Vec3 c =
        box.min() + (0.5 * (Vec3(u(rng), u(rng), u(rng)) + Vec3::Ones())).cwiseProduct(box.sizes());
    const double t0 = 3.0 * (0.5 * u(rng) + 0.5);
    const MotionSnapshot m0 = field.motionAt(t0);
    const FieldSample at = field.evaluate(c, r, m0);
    if (at.value <= 0.0) continue;
    InteriorBall ball = interiorBall(field, c, at, r, 2e-3, m0);
    ASSERT_GT(ball.radius, 0.0);
    ++certified;
    for (int j = 0; j < 5; ++j) {
      const MotionSnapshot m1 = field.motionAt(t0 + kDelays[j]);
      const Ball now = followBall(&ball, field, m1);
      ASSERT_TRUE(ball.sensed);
      const Vec3 shift = now.center - c;
      const double kappa = field.deformationRate(m0.regions, m1.regions);
      for (int k = 0; k < 20; ++k) {
        const Vec3 q = c + 2e-3 * std::abs(u(rng)) * Vec3(u(rng), u(rng), u(rng)).normalized();
        const double change =
            std::abs(field.evaluate(q + shift, r, m1).value - field.evaluate(q, r, m0).value);
        const double bound = ball.a * kappa + ball.b * kappa * kappa;
        if (now.radius > 0.0 || shift.norm() <= kBallSlack) {
          ASSERT_LE(change, bound + 1e-12) << "ball " << certified << " delay " << kDelays[j];
          if (bound > 0.0) tightest = std::max(tightest, change / bound);
        }
      }
      if (now.radius <= 0.0) continue;
      ++followed[j];
      for (int k = 0; k < 20; ++k, ++probes) {
        const Vec3 p = now.center + now.radius * std::abs(u(rng)) * 0.999999 *
                                        Vec3(u(rng), u(rng), u(rng)).normalized();
        ASSERT_GT(field.evaluate(p, r, m1).value, 0.0)
            << "ball " << certified << " delay " << kDelays[j] << " probe " << k;
      }
    }
  }
  std::printf(
      "[ metric   ] balls following the network's motion: %d certified; still holding after 1, 5, "
      "20, 100, 400 ms: %d, %d, %d, %d, %d; %d probes inside; the field's change at most %.3g "
      "of its bound\n",
      certified, followed[0], followed[1], followed[2], followed[3], followed[4], probes, tightest);
  ASSERT_EQ(certified, 300);
  EXPECT_GT(followed[1], certified / 2);  // the balls do follow (not vacuously true)
}

/// Tips after `steps` of a scene, with the certified balls on or off.
std::vector<Vec3> tipsAfter(const std::string& scene, long steps, bool balls, long* rows) {
  SceneModel model = loadScene(scene);
  model.contact.interior_balls = balls;
  SimData data = makeData(model);
  for (long k = 0; k < steps; ++k) EXPECT_EQ(step(model, &data), StepStatus::kOk) << k;
  std::vector<Vec3> tips;
  for (const DeviceState& d : data.devices) tips.push_back(d.position.back());
  *rows = data.stats.contact.contacts;
  return tips;
}

class BallsOnAndOff : public ::testing::TestWithParam<const char*> {};

TEST_P(BallsOnAndOff, FollowTheSameTrajectoryToTheLastBit) {
  // A ball only spares evaluations whose outcome it certifies (no root, no
  // violation, no tunnel): the trajectory cannot change at all. carotid
  // keeps its balls across steps; network's vessels move, and its balls
  // follow them.
  long with_rows = 0, without_rows = 0;
  const auto with = tipsAfter(GetParam(), 6000, true, &with_rows);
  const auto without = tipsAfter(GetParam(), 6000, false, &without_rows);
  ASSERT_EQ(with.size(), without.size());
  for (size_t i = 0; i < with.size(); ++i) EXPECT_EQ(with[i], without[i]) << i;
  EXPECT_EQ(with_rows, without_rows);
  EXPECT_GT(with_rows, 0);  // the wire is in contact by then
}

INSTANTIATE_TEST_SUITE_P(Scenes, BallsOnAndOff, ::testing::Values("carotid", "network"));

}  // namespace
}  // namespace evsim
