// The still blood's drag (effect 'blood_drag', mechanics/blood_drag.h)
// against slender-body theory's answers: a straight rod released in blood
// sinks with gravity at 30 degrees to its axis; it reaches the terminal
// velocity m' g_along / c_along along its axis and m' g_across / c_across
// across it (it drifts sideways, twice as fast along as across for the
// same pull), and approaches it as 1 - exp(-t / tau), tau = m' / c.
#include "endovascular_sim/mechanics/blood_drag.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/sim/simulation.h"
#include "test_helpers.h"

namespace evsim {
namespace {

constexpr double kG = 9.81;       // [m/s^2]
constexpr double kMu = 3.5e-3;    // [Pa s]
constexpr double kRadius = 2e-4;  // [m]
constexpr double kLength = 0.1;   // [m]

/// A straight wire (0.1 m, 20 elements) in free space with the blood's drag.
SceneModel rodInBlood() {
  SceneModel m;
  m.name = "rod in blood";
  m.time_step = 1e-3;
  m.effects.gravity = m.effects.blood_drag = true;
  m.devices.push_back(
      buildDeviceModel(straightDeviceSpec("wire", test::wireSection(60e9, kRadius), kLength, 20)));
  setBloodDrag(kMu, &m.devices[0]);
  m.introducers.push_back(Introducer{});
  m.initial_inserted_length.push_back(m.devices[0].length);
  m.initial_rotation.push_back(0.0);
  return m;
}

Vec3 meanVelocity(const DeviceState& s) {
  Vec3 v = Vec3::Zero();
  for (const Vec3& x : s.velocity) v += x;
  return v / static_cast<double>(s.velocity.size());
}

TEST(BloodDrag, ARodSinksAtSlenderBodyTheorysTerminalVelocityAlongAndAcrossItsAxis) {
  SceneModel m = rodInBlood();
  SimData d = makeData(m);
  d.devices[0].released = true;
  // (a step replaces d.devices: read it afresh after each)
  const std::vector<Vec3>& x0 = d.devices[0].position;
  const Vec3 along = (x0.back() - x0.front()).normalized();
  const Vec3 across = along.unitOrthogonal();
  const double theta = M_PI / 6.0;  // gravity 30 degrees off the axis
  m.gravity = kG * (std::cos(theta) * along + std::sin(theta) * across);
  double mass = 0.0;
  for (double x : m.devices[0].node_mass) mass += x;
  const double per_length = mass / m.devices[0].length;  // [kg/m]
  const double c_along = dragAlong(kMu, kLength, kRadius);
  const double c_across = dragAcross(kMu, kLength, kRadius);
  const double tau_across = per_length / c_across, tau_along = per_length / c_along;  // [s]
  // The transient after 0.1 s across the axis (implicit Euler's lag: dt /
  // tau of 1 %), then the terminal velocity after 3 s (13 tau along).
  const double t1 = 0.1;
  for (int k = 0; k < 100; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  const double v_across_t1 = meanVelocity(d.devices[0]).dot(across);
  const double terminal_across = per_length * kG * std::sin(theta) / c_across;
  const double terminal_along = per_length * kG * std::cos(theta) / c_along;
  const double expected_t1 = terminal_across * (1.0 - std::exp(-t1 / tau_across));
  EXPECT_NEAR(v_across_t1, expected_t1, 0.015 * expected_t1);
  for (int k = 100; k < 3000; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  const DeviceState& s = d.devices[0];
  const Vec3 v = meanVelocity(s);
  std::printf(
      "[ metric   ] rod in blood (mu %.1e Pa s, L/a %.0f): terminal velocity along %.6f m/s "
      "(theory %.6f), across %.6f m/s (theory %.6f), tau %.4f / %.4f s; across at 0.1 s %.5f "
      "(theory %.5f)\n",
      kMu, kLength / kRadius, v.dot(along), terminal_along, v.dot(across), terminal_across,
      tau_along, tau_across, v_across_t1, expected_t1);
  EXPECT_NEAR(v.dot(along), terminal_along, 1e-4 * terminal_along);
  EXPECT_NEAR(v.dot(across), terminal_across, 1e-4 * terminal_across);
  EXPECT_NEAR(v.dot(along.cross(across)), 0.0, 1e-6 * terminal_along);
  // The rod translates without turning: its axis keeps its direction.
  EXPECT_GT((s.position.back() - s.position.front()).normalized().dot(along), 1.0 - 1e-9);
}

TEST(BloodDrag, ARodThatIsNotSlenderGetsABoundedDrag) {
  // ln(L / a) at or below 1 (a short piece, a ball): the drag of L / a = e, never
  // an infinite or negative one.
  for (double L : {1e-3, 2.718e-3, 1e-4}) {
    EXPECT_DOUBLE_EQ(dragAcross(kMu, L, 1e-3), 4.0 * M_PI * kMu) << L;
    EXPECT_DOUBLE_EQ(dragAlong(kMu, L, 1e-3), 2.0 * M_PI * kMu) << L;
  }
  EXPECT_LT(dragAcross(kMu, 1.0, 1e-3), 4.0 * M_PI * kMu);  // slender: ln 1000
}

}  // namespace
}  // namespace evsim
