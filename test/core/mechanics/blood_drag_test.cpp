// The still blood's drag (effect 'blood_drag', mechanics/blood_drag.h)
// against answers found without the simulation: a straight rod released in
// blood sinks with gravity at 30 degrees to its axis; it reaches the
// terminal velocity m' g_along / c_along along its axis (slender-body
// theory) and across it the speed where the cylinder's drag 1/2 rho d C_D(Re)
// v^2 equals m' g_across (a root found by bisection); released broadside,
// its speed follows dv/dt = g - c(v) v / m' (integrated by RK4).
#include "endovascular_sim/mechanics/blood_drag.h"

#include <gtest/gtest.h>

#include <algorithm>
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
const Blood kBlood{kMu, 1060.0};

/// A straight wire (0.1 m, 20 elements) in free space with the blood's drag.
SceneModel rodInBlood(double time_step = 1e-3) {
  SceneModel m;
  m.name = "rod in blood";
  m.time_step = time_step;
  m.effects.gravity = m.effects.blood_drag = true;
  m.devices.push_back(
      buildDeviceModel(straightDeviceSpec("wire", test::wireSection(60e9, kRadius), kLength, 20)));
  setBloodDrag(kBlood, &m.devices[0]);
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

/// The rod's mass per unit length [kg/m].
double massPerLength(const DeviceModel& model) {
  double mass = 0.0;
  for (double x : model.node_mass) mass += x;
  return mass / model.length;
}

/// The drag force across per unit length [N/m] at speed v, from its
/// definition: the larger of 1/2 rho d C_D(Re) v^2 and Cox's c v.
double forceAcross(double v) {
  if (v <= 0.0) return 0.0;
  const double d = 2.0 * kRadius;
  const double re = kBlood.density * v * d / kMu;
  const double cylinder =
      0.5 * kBlood.density * d * (1.0 + 10.0 * std::pow(re, -2.0 / 3.0)) * v * v;
  return std::max(cylinder, dragAcross(kMu, kLength, kRadius) * v);
}

/// The speed across where the drag per unit length equals `pull` [N/m].
double terminalAcross(double pull) {
  double lo = 0.0, hi = 100.0;
  for (int it = 0; it < 200; ++it)
    (forceAcross(0.5 * (lo + hi)) < pull ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

TEST(BloodDrag, ARodSinksAtTheTerminalVelocityOfItsDragLawsAlongAndAcrossItsAxis) {
  SceneModel m = rodInBlood();
  SimData d = makeData(m);
  d.devices[0].released = true;
  // (a step replaces d.devices: read it afresh after each)
  const std::vector<Vec3>& x0 = d.devices[0].position;
  const Vec3 along = (x0.back() - x0.front()).normalized();
  const Vec3 across = along.unitOrthogonal();
  const double theta = M_PI / 6.0;  // gravity 30 degrees off the axis
  m.gravity = kG * (std::cos(theta) * along + std::sin(theta) * across);
  const double per_length = massPerLength(m.devices[0]);  // [kg/m]
  const double c_along = dragAlong(kMu, kLength, kRadius);
  const double tau_along = per_length / c_along;  // [s]
  // The terminal velocity after 3 s (13 tau along).
  for (int k = 0; k < 3000; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  const double terminal_across = terminalAcross(per_length * kG * std::sin(theta));
  const double terminal_along = per_length * kG * std::cos(theta) / c_along;
  const DeviceState& s = d.devices[0];
  const Vec3 v = meanVelocity(s);
  const double re = kBlood.density * terminal_across * 2.0 * kRadius / kMu;
  std::printf(
      "[ metric   ] rod in blood (mu %.1e Pa s, L/a %.0f): terminal velocity along %.6f m/s "
      "(slender-body theory %.6f, tau %.3f s), across %.6f m/s (cylinder's drag %.6f, Re %.1f; "
      "slender-body theory alone: %.6f)\n",
      kMu, kLength / kRadius, v.dot(along), terminal_along, tau_along, v.dot(across),
      terminal_across, re, per_length * kG * std::sin(theta) / dragAcross(kMu, kLength, kRadius));
  EXPECT_NEAR(v.dot(along), terminal_along, 1e-4 * terminal_along);
  EXPECT_NEAR(v.dot(across), terminal_across, 1e-4 * terminal_across);
  EXPECT_NEAR(v.dot(along.cross(across)), 0.0, 1e-6 * terminal_along);
  // The rod translates without turning: its axis keeps its direction.
  EXPECT_GT((s.position.back() - s.position.front()).normalized().dot(along), 1.0 - 1e-9);
}

TEST(BloodDrag, ARodReleasedBroadsideSpeedsUpAsItsDragLawsOrdinaryDifferentialEquation) {
  // Gravity across the axis; dt 0.1 ms (implicit Euler's lag dt / tau
  // about 0.5 %, its drag coefficient taken at the step's start).
  SceneModel m = rodInBlood(1e-4);
  SimData d = makeData(m);
  d.devices[0].released = true;
  const std::vector<Vec3>& x0 = d.devices[0].position;
  const Vec3 across = (x0.back() - x0.front()).normalized().unitOrthogonal();
  m.gravity = kG * across;
  const double per_length = massPerLength(m.devices[0]);
  auto dvdt = [&](double v) { return kG - forceAcross(v) / per_length; };
  double v = 0.0, t = 0.0;  // RK4 at 1 us
  const double h = 1e-6;
  for (int k : {100, 200, 500}) {  // [steps of 0.1 ms]: 10, 20 and 50 ms
    for (int i = static_cast<int>(std::lround(t / m.time_step)); i < k; ++i)
      ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
    for (; t < k * m.time_step - 0.5 * h; t += h) {
      const double k1 = dvdt(v), k2 = dvdt(v + 0.5 * h * k1), k3 = dvdt(v + 0.5 * h * k2),
                   k4 = dvdt(v + h * k3);
      v += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    const double simulated = meanVelocity(d.devices[0]).dot(across);
    std::printf("[ metric   ] rod released broadside in blood: %.0f ms %.6f m/s (ODE %.6f)\n",
                1e3 * t, simulated, v);
    EXPECT_NEAR(simulated, v, 0.01 * v) << t;
  }
  // The drag slowed it: without it, g t.
  EXPECT_LT(v, 0.5 * kG * t);
}

TEST(BloodDrag, TheCylindersDragTakesOverFromSlenderBodyTheoryAsTheSpeedGrows) {
  // White's fit at Re 1 and 1000; at a crawl Cox's drag is the larger.
  EXPECT_DOUBLE_EQ(cylinderDragCoefficient(1.0), 11.0);
  EXPECT_NEAR(cylinderDragCoefficient(1000.0), 1.1, 1e-12);
  const double cox = dragAcross(kMu, kLength, kRadius);
  EXPECT_DOUBLE_EQ(dragAcrossAt(kBlood, kLength, kRadius, 1e-6), cox);
  for (double v : {0.01, 0.1, 1.0, 3.0}) {
    const double re = kBlood.density * v * 2.0 * kRadius / kMu;
    const double expected = 0.5 * kBlood.density * 2.0 * kRadius * v * cylinderDragCoefficient(re);
    EXPECT_NEAR(dragAcrossAt(kBlood, kLength, kRadius, v), expected, 1e-12 * expected) << v;
    EXPECT_GT(expected, cox) << v;
  }
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
