// Implicit Euler free motion: rest stays rest, damping dissipates, and the
// introducer drives insertion and rotation exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/mechanics/implicit_euler.h"
#include "endovascular_sim/mechanics/introducer.h"
#include "test_helpers.h"

namespace evsim {
namespace {

/// Nitinol guidewire with a J-tip: 0.3 m shaft, 2 cm tip bent by 180 degrees.
DeviceModel jTipGuidewire(int shaft_elements = 60) {
  DeviceSpec spec;
  spec.name = "guidewire";
  DeviceSectionSpec shaft;
  shaft.name = "shaft";
  shaft.section = test::wireSection(60e9, 1.78e-4);
  shaft.length = 0.3;
  shaft.elements = shaft_elements;
  DeviceSectionSpec tip = shaft;
  tip.name = "tip";
  tip.length = 0.02;
  tip.elements = 20;
  tip.section = test::wireSection(40e9, 1.2e-4);
  tip.rest_curvature = Vec3(0.0, 0.0, M_PI / tip.length);
  spec.sections = {shaft, tip};
  spec.rayleigh_mass = 1.0;
  return buildDeviceModel(spec);
}

double maxDistance(const DeviceState& a, const DeviceState& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.position.size(); ++i)
    d = std::max(d, (a.position[i] - b.position[i]).norm());
  return d;
}

TEST(DeviceModel, RestShapeOfConstantCurvatureIsACircularArc) {
  const DeviceModel m = jTipGuidewire();
  // The 2 cm tip is a half circle of radius 2 cm / pi starting at (0.3, 0, 0)
  // along x and bending toward +y: it ends at (0.3, 2 r, 0), pointing back.
  const double r = 0.02 / M_PI;
  EXPECT_LT((m.rest_position.back() - Vec3(0.3, 2.0 * r, 0.0)).norm(), 1e-12);
  EXPECT_LT((m.rest_rotation.back().col(0) - Vec3(-1.0, 0.0, 0.0)).norm(), 1e-12);
  EXPECT_NEAR(m.length, 0.32, 1e-15);
}

TEST(Dynamics, PreShapedDeviceAtRestStaysAtRest) {
  const DeviceModel m = jTipGuidewire();
  Introducer intro;
  intro.frame = expSO3(Vec3(0.2, -0.4, 0.3));
  DeviceState state = placeDevice(m, intro, 0.1, 0.7);
  const DeviceState start = state;
  EXPECT_LT(elasticEnergy(m, state), 1e-20);
  DeviceWorkspace ws;
  for (int k = 0; k < 1000; ++k) {
    ASSERT_TRUE(computeFreeMotion(m, intro, Vec3::Zero(), 1e-3, state, &ws));
    commitMotion(ws.dq, 1e-3, &state);
  }
  EXPECT_LT(maxDistance(state, start), 1e-12);
}

TEST(Dynamics, RigidMotionOfWholeDeviceGivesZeroElasticForce) {
  const DeviceModel m = jTipGuidewire();
  std::mt19937 rng(11);
  for (int k = 0; k < 10; ++k) {
    const DeviceState s = restState(m, test::randomRotation(&rng), Vec3(0.1, -0.2, 0.3 * k));
    VecX g;
    assembleElasticity(m, s, &g, nullptr);
    // Round-off only: a strain of 1e-12 of the axial stiffness EA.
    const double ea = m.elements[0].stretch_shear_stiffness.x();
    EXPECT_LT(g.lpNorm<Eigen::Infinity>(), 1e-12 * ea);
  }
}

/// Total mechanical energy of a cantilever released from a bent shape.
std::vector<double> releasedCantileverEnergy(double rayleigh_mass, double rayleigh_stiffness) {
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, 1.78e-4), 0.2, 40);
  spec.rayleigh_mass = rayleigh_mass;
  spec.rayleigh_stiffness = rayleigh_stiffness;
  const DeviceModel m = buildDeviceModel(spec);
  Introducer intro;
  DeviceState state = placeDevice(m, intro, m.length - 0.001, 0.0);
  for (int i = 1; i < m.num_nodes; ++i) {  // bend it: initial elastic energy
    const double s = m.node_s[i] - m.node_s[1];
    state.position[i].y() += 0.02 * s * s / (m.length * m.length);
  }
  DeviceWorkspace ws;
  std::vector<double> energy;
  for (int k = 0; k < 400; ++k) {
    energy.push_back(kineticEnergy(m, state) + elasticEnergy(m, state));
    EXPECT_TRUE(computeFreeMotion(m, intro, Vec3::Zero(), 1e-3, state, &ws));
    commitMotion(ws.dq, 1e-3, &state);
  }
  return energy;
}

TEST(Dynamics, DampingMakesEnergyDecrease) {
  const std::vector<double> light = releasedCantileverEnergy(0.5, 1e-4);
  const std::vector<double> heavy = releasedCantileverEnergy(20.0, 1e-3);
  for (size_t k = 1; k < light.size(); ++k) {
    EXPECT_LE(light[k], light[k - 1] * (1.0 + 1e-12)) << "step " << k;
    EXPECT_LE(heavy[k], heavy[k - 1] * (1.0 + 1e-12)) << "step " << k;
  }
  EXPECT_LT(light.back(), 0.9 * light.front());
  EXPECT_LT(heavy.back(), light.back());
}

/// Tip deflection across a 0.1 m nitinol cantilever, released from 0.1 mm
/// (linear range) of a quadratic shape, every step for `steps` steps.
std::vector<double> cantileverTipDeflection(double rayleigh_stiffness, int steps, double dt) {
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, 1.78e-4), 0.1, 40);
  spec.rayleigh_stiffness = rayleigh_stiffness;
  const DeviceModel m = buildDeviceModel(spec);
  Introducer intro;
  DeviceState state = placeDevice(m, intro, m.length - 0.001, 0.0);
  for (int i = 1; i < m.num_nodes; ++i) {
    const double s = m.node_s[i] - m.node_s[1];
    state.position[i].y() += 1e-4 * s * s / (m.length * m.length);
  }
  DeviceWorkspace ws;
  std::vector<double> tip;
  for (int k = 0; k < steps; ++k) {
    EXPECT_TRUE(computeFreeMotion(m, intro, Vec3::Zero(), dt, state, &ws));
    commitMotion(ws.dq, dt, &state);
    tip.push_back(state.position.back().y());
  }
  return tip;
}

/// The positive peaks of a sampled oscillation (local maxima above zero).
std::vector<std::pair<int, double>> positivePeaks(const std::vector<double>& y) {
  std::vector<std::pair<int, double>> peaks;
  for (size_t k = 1; k + 1 < y.size(); ++k)
    if (y[k] > 0.0 && y[k] >= y[k - 1] && y[k] > y[k + 1]) peaks.emplace_back(k, y[k]);
  return peaks;
}

/// One step of linearised implicit Euler on a mode of angular frequency w
/// with damping c = alpha + beta w^2: (q, v) -> B (q, v); its complex
/// eigenvalue z (|z| the amplitude's factor per step, arg z the phase).
std::complex<double> modalStepEigenvalue(double w, double c, double dt) {
  const double a = 1.0 / dt + c + w * w * dt;
  const double b11 = 1.0 - dt * w * w / a, b12 = 1.0 / a;
  const double b21 = -w * w / a, b22 = 1.0 / (dt * a);
  const double tr = b11 + b22, det = b11 * b22 - b12 * b21;
  return {tr / 2.0, std::sqrt(std::max(0.0, det - tr * tr / 4.0))};
}

TEST(Dynamics, StiffnessDampingDecaysTheFirstModeAtTheDiscreteRate) {
  // The first bending mode of a cantilever, without and with beta = 1 ms
  // (the shipped devices' value): its decay per step against the modal
  // recurrence of implicit Euler, exact for a linear mode, with w found
  // from the undamped run's period. Higher modes die within the first
  // periods (zeta = beta w / 2 > 0.3 from the second mode on); the peaks
  // are read after them.
  const double dt = 1e-3, beta = 1e-3;
  const int steps = 800;
  double w = 0.0;  // [rad/s] from the undamped run
  for (const double b : {0.0, beta}) {
    const std::vector<std::pair<int, double>> peaks =
        positivePeaks(cantileverTipDeflection(b, steps, dt));
    ASSERT_GE(peaks.size(), 6u);
    const auto& first = peaks[2];
    const auto& last = peaks[peaks.size() - 2];
    const int cycles = static_cast<int>(peaks.size()) - 4;
    const double period_steps = double(last.first - first.first) / cycles;
    const double measured = std::pow(last.second / first.second, 1.0 / (last.first - first.first));
    if (b == 0.0) {  // w from the discrete phase per step: arg z(w, 0) = 2 pi / period
      const double phase = 2.0 * M_PI / period_steps;
      double lo = 1.0, hi = 1e4;
      for (int it = 0; it < 200; ++it) {
        const double mid = std::sqrt(lo * hi);
        (std::arg(modalStepEigenvalue(mid, 0.0, dt)) < phase ? lo : hi) = mid;
      }
      w = lo;
    } else {  // the damped mode's phase per step, predicted from that w
      EXPECT_NEAR(2.0 * M_PI / period_steps, std::arg(modalStepEigenvalue(w, b * w * w, dt)),
                  0.02 * 2.0 * M_PI / period_steps);
    }
    const double predicted = std::abs(modalStepEigenvalue(w, b * w * w, dt));
    std::printf(
        "[ metric   ] beta %g s: w %.2f rad/s, decay per step %.6f, predicted %.6f (%.2f %% of the "
        "log)\n",
        b, w, measured, predicted,
        100.0 * std::abs(std::log(measured) / std::log(predicted) - 1.0));
    EXPECT_NEAR(std::log(measured), std::log(predicted), 0.01 * std::abs(std::log(predicted)))
        << "beta " << b << ": w " << w << " rad/s, period " << period_steps << " steps";
    if (b > 0.0) {
      // The decay beta adds is about beta w^2 / 2 per second: not nothing.
      EXPECT_GT(-std::log(measured) / dt, 0.5 * b * w * w);
    }
  }
}

class Drive : public ::testing::Test {
 protected:
  void SetUp() override {
    DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(60e9, 1.78e-4), 0.4, 100);
    spec.rayleigh_mass = 5.0;
    spec.max_insertion_speed = 0.05;
    spec.max_rotation_speed = 2.0 * M_PI;
    model = buildDeviceModel(spec);
    intro.access_point = Vec3(0.01, 0.02, -0.03);
    intro.frame = expSO3(Vec3(0.3, 0.1, -0.5));
    state = placeDevice(model, intro, 0.1, 0.0);
  }

  void run(const DriveCommand& cmd, double seconds) {
    const double dt = 1e-3;
    for (int k = 0; k < static_cast<int>(seconds / dt + 0.5); ++k) {
      advanceDrive(cmd, model, dt, &state);
      ASSERT_TRUE(computeFreeMotion(model, intro, Vec3::Zero(), dt, state, &ws));
      commitMotion(ws.dq, dt, &state);
    }
  }

  DeviceModel model;
  Introducer intro;
  DeviceState state;
  DeviceWorkspace ws;
};

TEST_F(Drive, InsertionMovesTheTipByTheCommandedLength) {
  const Vec3 tip0 = state.position.back();
  DriveCommand cmd;
  cmd.insertion = 0.02;  // [m/s] for 2.5 s: 50 mm
  run(cmd, 2.5);
  cmd.insertion = 0.0;
  run(cmd, 1.0);  // settle
  EXPECT_NEAR(state.inserted_length, 0.15, 1e-12);
  const Vec3 moved = state.position.back() - tip0;
  EXPECT_NEAR(moved.dot(intro.frame.col(0)), 0.05, 1e-7);
  EXPECT_LT((moved - 0.05 * intro.frame.col(0)).norm(), 1e-7);
}

TEST_F(Drive, RotationTurnsTheTipByTheCommandedAngle) {
  const Mat3 tip0 = state.rotation.back().toRotationMatrix();
  DriveCommand cmd;
  cmd.mode = DriveCommand::Mode::kPosition;
  cmd.insertion = 0.1;
  cmd.rotation = M_PI / 2;
  run(cmd, 2.0);
  const Vec3 turn = logSO3(tip0.transpose() * state.rotation.back().toRotationMatrix());
  EXPECT_NEAR(turn.x(), M_PI / 2, 1e-6);  // about the device axis
  EXPECT_NEAR(turn.tail<2>().norm(), 0.0, 1e-6);
}

TEST_F(Drive, CommandsBeyondLimitsOrNotFiniteAreRefused) {
  DriveCommand cmd;
  cmd.insertion = 0.06;
  EXPECT_NE(validateDriveCommand(cmd, model).find("exceeds the limit"), std::string::npos);
  cmd.insertion = std::nan("");
  EXPECT_NE(validateDriveCommand(cmd, model).find("finite"), std::string::npos);
  cmd = DriveCommand{DriveCommand::Mode::kPosition, 0.5, 0.0};
  EXPECT_NE(validateDriveCommand(cmd, model).find("outside"), std::string::npos);
  cmd.insertion = 0.2;
  EXPECT_EQ(validateDriveCommand(cmd, model), "");
}

}  // namespace
}  // namespace evsim
