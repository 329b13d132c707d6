// The sheath's hold on the element leaving it (mechanics/sheath_support.h):
// its gradient against central differences of its energy, its tangent
// against differences of the gradient where the hold is satisfied (there
// the Gauss-Newton tangent is the exact one), and its two ends: at f -> 1
// the element's clamped stiffnesses times the factor on the node's offset
// and tilt, at f = 0 nothing.
#include "endovascular_sim/mechanics/sheath_support.h"

#include <gtest/gtest.h>

#include <random>

#include "endovascular_sim/mechanics/so3.h"
#include "test_helpers.h"

namespace evsim {
namespace {

struct HoldCase {
  DeviceModel model;
  Introducer intro;
  DeviceState state;
  int held{0};
};

/// A steel wire of 2 mm elements, 30 mm inserted plus `fraction` of an
/// element still in the sheath, its first free node moved off the axis and
/// turned by (offset, tilt).
HoldCase holdCase(double fraction, const Vec3& offset, const Vec3& tilt) {
  HoldCase s;
  s.model = buildDeviceModel(
      straightDeviceSpec("wire", test::wireSection(200e9, 0.25e-3, 7900.0), 0.2, 100));
  s.intro.frame = Eigen::AngleAxisd(0.3, Vec3(0.2, 1.0, -0.4).normalized()).toRotationMatrix();
  s.intro.access_point = Vec3(0.01, -0.02, 0.03);
  const double L = 0.002;
  const double inserted = 0.03 + (1.0 - fraction) * L;  // s_a = 0.17 - (1 - f) L
  s.state = placeDevice(s.model, s.intro, inserted, 0.0);
  s.held = lastHeldNode(s.model, inserted);
  const int j = s.held + 1;
  s.state.position[j] += offset;
  s.state.rotation[j] = expQuaternion(tilt) * s.state.rotation[j];
  return s;
}

double energyAt(HoldCase s, const Vec6& dq) {
  const int j = s.held + 1;
  s.state.position[j] += dq.head<3>();
  s.state.rotation[j] = expQuaternion(dq.tail<3>()) * s.state.rotation[j];
  return sheathHold(s.model, s.intro, s.state, s.held).energy;
}

TEST(SheathHold, GradientAndTangentAreTheEnergysDerivatives) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double f : {0.9, 0.5, 0.2}) {
    const HoldCase s = holdCase(f, 1e-5 * Vec3(u(random), u(random), u(random)),
                                0.02 * Vec3(u(random), u(random), u(random)));
    const SheathHold h = sheathHold(s.model, s.intro, s.state, s.held);
    ASSERT_EQ(h.node, s.held + 1);
    EXPECT_NEAR(h.fraction, f, 1e-9);
    ASSERT_GT(h.energy, 0.0);
    Vec6 numeric;
    for (int i = 0; i < 6; ++i) {
      const double eps = i < 3 ? 1e-8 : 1e-6;
      Vec6 d = Vec6::Zero();
      d(i) = eps;
      numeric(i) = (energyAt(s, d) - energyAt(s, -d)) / (2.0 * eps);
    }
    EXPECT_LT((numeric - h.gradient).norm(), 1e-6 * h.gradient.norm()) << "f = " << f;

    // On the axis and along it the hold is satisfied: the tangent is exact.
    const HoldCase rest = holdCase(f, Vec3::Zero(), Vec3::Zero());
    const SheathHold h0 = sheathHold(rest.model, rest.intro, rest.state, rest.held);
    EXPECT_LT(h0.gradient.norm(), 1e-9 * h.gradient.norm());
    for (int i = 0; i < 6; ++i) {
      const double eps = i < 3 ? 1e-9 : 1e-7;
      Vec6 d = Vec6::Zero();
      d(i) = eps;
      HoldCase plus = rest, minus = rest;
      const int j = rest.held + 1;
      plus.state.position[j] += d.head<3>();
      plus.state.rotation[j] = expQuaternion(d.tail<3>()) * plus.state.rotation[j];
      minus.state.position[j] -= d.head<3>();
      minus.state.rotation[j] = expQuaternion(-d.tail<3>()) * minus.state.rotation[j];
      const Vec6 column = (sheathHold(plus.model, plus.intro, plus.state, plus.held).gradient -
                           sheathHold(minus.model, minus.intro, minus.state, minus.held).gradient) /
                          (2.0 * eps);
      EXPECT_LT((column - h0.hessian.col(i)).norm(), 1e-5 * h0.hessian.norm())
          << "f = " << f << ", column " << i;
    }
  }
}

TEST(SheathHold, HoldsAJustReleasedNodeAsAClampAndFadesToNothing) {
  const double L = 0.002;
  const double EI = 200e9 * M_PI * std::pow(0.25e-3, 4) / 4.0;
  const Vec3 offset(0.0, 1e-5, 0.0), tilt(0.0, 0.0, 0.01);
  const Mat3 R = holdCase(0.5, Vec3::Zero(), Vec3::Zero()).intro.frame;  // the sheath's frame
  const HoldCase near1 = holdCase(1.0 - 1e-6, R * offset, R * tilt);
  const SheathHold h = sheathHold(near1.model, near1.intro, near1.state, near1.held);
  // Offset y across, tilt: the tangent turns by 0.01 rad across the axis.
  const double tilted = std::sin(0.01);
  const double expected =
      0.5 * kSheathHoldFactor * (12.0 * EI / (L * L * L) * 1e-10 + 4.0 * EI / L * tilted * tilted);
  EXPECT_NEAR(h.energy, expected, 1e-4 * expected);
  const HoldCase at0 = holdCase(1e-13, R * offset, R * tilt);
  EXPECT_LT(sheathHold(at0.model, at0.intro, at0.state, at0.held).energy, 1e-20);
}

}  // namespace
}  // namespace evsim
