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
  m.effects.friction = true;
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
      std::tan(theta), mu, a, expected, distance, d.stats.contact.sliding_contacts);
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

/// The outside of a cylinder of radius R about the z axis (a capstan):
/// g = |p_xy| - R - r.
class CapstanSurface : public ImplicitSurface {
 public:
  explicit CapstanSurface(double radius) : radius_(radius) {}
  FieldSample evaluate(const Vec3& p, double r, const MotionSnapshot& = {}) const override {
    const Vec3 radial(p.x(), p.y(), 0.0);
    FieldSample s;
    s.value = radial.norm() - radius_ - r;
    s.gradient = radial.normalized();
    return s;
  }
  double hessianBound(const Vec3&, const Vec3&, double) const override { return 2.0 / radius_; }

 private:
  double radius_;
};

// The capstan: a thread (polymer, E = 50 MPa, radius 0.1 mm) rises from its
// introducer, wraps half a turn over a cylinder of radius 10 mm and hangs
// with a 1 g weight on its tip. Pulled back at 10 mm/s it slides over the
// cylinder, and the tensions on both sides of the wrap follow the capstan
// law T_pull = T_load e^(mu pi). Tension against bending stiffness:
// T R^2 / EI ~ 250, so the thread is nearly a string. T_load is the hanging
// weight; T_pull - T_load is the sum of the friction forces on the wrap.
TEST(Capstan, PullingOverACylinderNeedsTheCapstanForceRatio) {
  const double mu = 0.2, cylinder = 0.01, radius = 1e-4, tip_mass = 1e-3;
  const double rho = cylinder + radius + 1e-6;  // the thread's axis on the wrap [m]
  const double up = 0.04, down = 0.06, held = 0.01;
  const double inserted = up + M_PI * rho + down;
  SceneModel m;
  m.name = "capstan";
  m.time_step = 1e-3;
  m.effects.gravity = m.effects.friction = true;
  m.gravity = Vec3(0.0, -kG, 0.0);
  DeviceSpec spec = straightDeviceSpec("thread", test::wireSection(5e7, radius), held + inserted,
                                       static_cast<int>(std::round((held + inserted) / 2e-3)));
  spec.sections[0].friction = mu;
  spec.rayleigh_stiffness = 5e-3;
  m.devices.push_back(buildDeviceModel(spec));
  m.devices[0].node_mass.back() += tip_mass;
  Introducer intro;
  intro.access_point = Vec3(-rho, -up, 0.0);
  intro.frame << 0, -1, 0, 1, 0, 0, 0, 0, 1;  // x axis up (+y)
  m.introducers.push_back(intro);
  m.initial_inserted_length.push_back(inserted);
  m.initial_rotation.push_back(0.0);
  m.surface = std::make_shared<CapstanSurface>(cylinder);
  m.effects.friction = true;
  // Sampled between the nodes too: redundant rows (cond W ~ 1e17). Before
  // the non-monotone line search (session 9) Newton stalled on them and the
  // test sampled the nodes only; the ratio is the same (1.8272 at the nodes,
  // 1.8273 at 1 mm, 1.8291 at 0.5 mm).
  m.contact.contact_spacing = 1e-3;
  m.samples.push_back(sampleDevice(m.devices[0], m.contact.contact_spacing));

  SimData d = makeData(m);
  // Lay the inserted thread on its path: up, half a turn, down.
  const DeviceModel& dev = m.devices[0];
  DeviceState& x = d.devices[0];  // (step() swaps the states: not used after it)
  for (int i = 0; i < dev.num_nodes; ++i) {
    const double sigma = dev.node_s[i] - (dev.length - inserted);
    if (sigma <= 0.0) continue;
    Vec3 p;
    double heading;  // angle of the tangent about z
    if (sigma <= up) {
      p = Vec3(-rho, -up + sigma, 0.0);
      heading = M_PI / 2;
    } else if (sigma <= up + M_PI * rho) {
      const double psi = M_PI - (sigma - up) / rho;
      p = Vec3(rho * std::cos(psi), rho * std::sin(psi), 0.0);
      heading = psi - M_PI / 2;
    } else {
      p = Vec3(rho, -(sigma - up - M_PI * rho), 0.0);
      heading = -M_PI / 2;
    }
    x.position[i] = p;
    x.rotation[i] = Quat(Eigen::AngleAxisd(heading, Vec3::UnitZ()));
  }
  // Averaged over the last 400 steps: over 100, a change of the round-off
  // alone moved the ratio by 1 % (1.834 and 1.817), over 400 by 0.1 %.
  const int settle = 100, pull = 1000, window = 400;
  for (int k = 0; k < settle; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  ASSERT_EQ(setCommand(m, &d, "thread", {DriveCommand::Mode::kVelocity, -0.01, 0.0}), "");
  double friction_sum = 0.0, load = 0.0;
  int sliding = 0;
  for (int k = 0; k < pull; ++k) {
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << "step " << k << ": " << d.last_error;
    if (k < pull - window) continue;
    for (const Contact& c : d.contacts) friction_sum += c.friction.norm() / window;
    for (int i = 0; i < dev.num_nodes; ++i)  // the hanging part, below the wrap
      if (d.devices[0].position[i].x() > 0.0 && d.devices[0].position[i].y() < 0.0)
        load += dev.node_mass[i] * kG / window;
    sliding = d.stats.contact.sliding_contacts;
  }
  const double ratio = (load + friction_sum) / load, expected = std::exp(mu * M_PI);
  std::printf(
      "[ metric   ] capstan mu=%.2f over pi: T_pull/T_load = %.4f (e^(mu pi) = %.4f), load %.4e N, "
      "%d sliding contacts\n",
      mu, ratio, expected, load, sliding);
  EXPECT_NEAR(ratio, expected, 0.03 * expected);
  EXPECT_GT(sliding, 10);
}

}  // namespace
}  // namespace evsim
