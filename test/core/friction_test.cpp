// Coulomb friction through the whole step (effect 'friction') against
// analytic answers: the inclined plane, the capstan law, and the energy
// friction dissipates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "endovascular_sim/geometry/implicit_surface.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/sim/simulation.h"
#include "test_helpers.h"

namespace evsim {
namespace {

constexpr double kG = 9.81;  // [m/s^2]

/// A straight wire (0.1 m, 20 elements, friction mu) released on the floor
/// z = 0, under gravity tilted by theta about y: an inclined plane whose
/// downhill direction is +x.
SceneModel wireOnIncline(double theta, double mu) {
  SceneModel m;
  m.name = "incline";
  m.time_step = 1e-3;
  m.effects.gravity = m.effects.friction = true;
  m.gravity = kG * Vec3(std::sin(theta), 0.0, -std::cos(theta));
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, 2e-4), 0.1, 20);
  spec.sections[0].friction = mu;
  m.devices.push_back(buildDeviceModel(spec));
  Introducer intro;
  intro.access_point = Vec3(0, 0, 2e-4 + 1e-6);  // 1 um above the floor
  m.introducers.push_back(intro);
  m.initial_inserted_length.push_back(m.devices[0].length);
  m.initial_rotation.push_back(0.0);
  m.surface = std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitZ());
  m.contact.friction = true;
  m.contact.contact_spacing = 5e-3;
  m.samples.push_back(sampleDevice(m.devices[0], m.contact.contact_spacing));
  return m;
}

double meanVelocityX(const DeviceState& s) {
  double v = 0.0;
  for (const Vec3& x : s.velocity) v += x.x();
  return v / s.velocity.size();
}

/// Potential energy of gravity [J] (g constant).
double potentialEnergy(const SceneModel& m, const DeviceState& s) {
  double e = 0.0;
  for (size_t i = 0; i < s.position.size(); ++i)
    e -= m.devices[0].node_mass[i] * m.gravity.dot(s.position[i]);
  return e;
}

struct InclineCase {
  double tan_theta, mu;
};

class Incline : public ::testing::TestWithParam<InclineCase> {};

TEST_P(Incline, StaysBelowTheFrictionAngleAndSlidesWithTheAnalyticAccelerationAbove) {
  const double theta = std::atan(GetParam().tan_theta), mu = GetParam().mu;
  const SceneModel m = wireOnIncline(theta, mu);
  SimData d = makeData(m);
  d.devices[0].released = true;
  const int settle = 50, run = 400;
  for (int k = 0; k < settle; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  const double v0 = meanVelocityX(d.devices[0]), x0 = d.devices[0].position[0].x();
  double energy = kineticEnergy(m.devices[0], d.devices[0]) + potentialEnergy(m, d.devices[0]);
  const double e0 = energy;
  double mass = 0.0;
  for (double x : m.devices[0].node_mass) mass += x;
  // Resting points may move within the contact tolerance band: energy noise
  // of at most the weight times that band.
  const double noise = mass * kG * m.contact.penetration_tolerance;
  for (int k = 0; k < run; ++k) {
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
    // Friction only dissipates: the total energy never grows.
    const double e = kineticEnergy(m.devices[0], d.devices[0]) + potentialEnergy(m, d.devices[0]);
    EXPECT_LE(e, energy + noise) << "step " << k;
    energy = e;
  }
  const double t = run * m.time_step;
  const double a = (meanVelocityX(d.devices[0]) - v0) / t;
  const double distance = d.devices[0].position[0].x() - x0;
  const double expected = tan(theta) <= mu ? 0.0 : kG * (std::sin(theta) - mu * std::cos(theta));
  std::printf(
      "[ metric   ] incline tan=%.2f mu=%.2f: a = %.6f m/s^2 (analytic %.6f), slid %.3e m, "
      "%d sliding contacts\n",
      std::tan(theta), mu, a, expected, distance, d.stats.sliding_contacts);
  if (expected == 0.0) {
    EXPECT_LT(std::abs(distance), 1e-7);  // sticks: below 0.1 um in 0.4 s
    EXPECT_LT(std::abs(a), 1e-4);
  } else {
    EXPECT_NEAR(a, expected, 0.01 * expected);
    // The energy lost is the work of kinetic friction, mu N d, plus implicit
    // Euler's own loss under the constant net force m a: m a dt (v1 - v0) / 2.
    const double work = mu * mass * kG * std::cos(theta) * distance;
    const double euler = mass * a * m.time_step * (meanVelocityX(d.devices[0]) - v0) / 2.0;
    EXPECT_NEAR(e0 - energy, work + euler, 0.002 * work);
  }
}

INSTANTIATE_TEST_SUITE_P(Angles, Incline,
                         ::testing::Values(InclineCase{0.2, 0.3}, InclineCase{0.29, 0.3},
                                           InclineCase{0.32, 0.3}, InclineCase{0.6, 0.3},
                                           InclineCase{0.6, 0.05}));

}  // namespace
}  // namespace evsim
