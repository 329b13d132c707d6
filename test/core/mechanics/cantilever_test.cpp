// Cantilevers against textbook answers.
//
//   clamp |=================================o  tip load P (down) or torque T
//         0                                 L
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/static_equilibrium.h"
#include "test_helpers.h"

namespace evsim {
namespace {

constexpr double kLength = 1.0;   // [m]
constexpr double kRadius = 1e-3;  // [m]: slenderness 1000, extension negligible
constexpr int kElements = 50;

struct Cantilever {
  DeviceModel model;
  DeviceState state;
  double EI, GJ, kGA;
};

Cantilever makeCantilever() {
  const BeamSection s = test::wireSection(2e9, kRadius);
  Cantilever c{buildDeviceModel(straightDeviceSpec("beam", s, kLength, kElements)), {}, 0, 0, 0};
  c.state = restState(c.model);
  c.EI = s.bendTwistStiffness().y();
  c.GJ = s.bendTwistStiffness().x();
  c.kGA = s.stretchShearStiffness().y();
  return c;
}

Vec3 solveTipLoad(Cantilever* c, const Vec6& tip_wrench, int load_steps) {
  std::vector<Vec6> wrenches(c->model.num_nodes, Vec6::Zero());
  wrenches.back() = tip_wrench;
  StaticOptions options;
  options.load_steps = load_steps;
  const StaticResult r = solveStaticEquilibrium(c->model, 1, wrenches, options, &c->state);
  EXPECT_TRUE(r.converged) << "residual " << r.residual;
  return c->state.position.back();
}

TEST(Cantilever, SmallTipLoadMatchesTimoshenkoFormula) {
  Cantilever c = makeCantilever();
  const double P = 1e-4 * c.EI / (kLength * kLength);
  Vec6 w;
  w << 0.0, -P, 0.0, 0.0, 0.0, 0.0;
  const Vec3 tip = solveTipLoad(&c, w, 1);
  const double expected =
      P * std::pow(kLength, 3) / (3.0 * c.EI) + P * kLength / c.kGA;  // bending + shear
  EXPECT_NEAR(-tip.y(), expected, 0.005 * expected);
  std::printf("[ metric   ] small load: deflection error %.4f %%\n",
              100.0 * std::abs(-tip.y() - expected) / expected);
}

/// Inextensible elastica under a dead tip load, by shooting on
///   EI theta'' = -P cos(theta),  theta(0) = 0,  theta'(L) = 0,
/// with tangent (cos theta, -sin theta); returns the tip (x, y).
Eigen::Vector2d elasticaTip(double load_parameter /* P L^2 / EI */) {
  const int steps = 20000;
  const double h = 1.0 / steps;  // unit length, EI = 1, P = load_parameter
  const double P = load_parameter;
  auto shoot = [&](double slope0, Eigen::Vector2d* tip) {
    // State: theta, theta', x, y.
    Eigen::Vector4d z(0.0, slope0, 0.0, 0.0);
    auto f = [P](const Eigen::Vector4d& s) {
      return Eigen::Vector4d(s(1), -P * std::cos(s(0)), std::cos(s(0)), -std::sin(s(0)));
    };
    for (int i = 0; i < steps; ++i) {
      const Eigen::Vector4d k1 = f(z), k2 = f(z + 0.5 * h * k1), k3 = f(z + 0.5 * h * k2),
                            k4 = f(z + h * k3);
      z += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    if (tip) *tip = z.tail<2>();
    return z(1);  // theta'(L)
  };
  double lo = 0.0, hi = P;  // theta'(L) < 0 at lo, >= 0 at hi
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(mid, nullptr) < 0.0 ? lo : hi) = mid;
  }
  Eigen::Vector2d tip;
  shoot(0.5 * (lo + hi), &tip);
  return tip;
}

class LargeDeflection : public ::testing::TestWithParam<double> {};

TEST_P(LargeDeflection, TipMatchesElastica) {
  const double load_parameter = GetParam();
  Cantilever c = makeCantilever();
  const double P = load_parameter * c.EI / (kLength * kLength);
  Vec6 w;
  w << 0.0, -P, 0.0, 0.0, 0.0, 0.0;
  const Vec3 tip = solveTipLoad(&c, w, 10);
  const Eigen::Vector2d ref = kLength * elasticaTip(load_parameter);
  EXPECT_NEAR(tip.x(), ref.x(), 0.01 * std::abs(ref.x())) << "PL^2/EI = " << load_parameter;
  EXPECT_NEAR(tip.y(), ref.y(), 0.01 * std::abs(ref.y())) << "PL^2/EI = " << load_parameter;
  EXPECT_NEAR(tip.z(), 0.0, 1e-12);
  std::printf("[ metric   ] PL^2/EI = %g: tip error x %.4f %%, y %.4f %%\n", load_parameter,
              100.0 * std::abs(tip.x() - ref.x()) / std::abs(ref.x()),
              100.0 * std::abs(tip.y() - ref.y()) / std::abs(ref.y()));
}

INSTANTIATE_TEST_SUITE_P(Elastica, LargeDeflection, ::testing::Values(1.0, 2.0, 5.0, 10.0));

TEST(Cantilever, TorsionAngleMatchesTLOverGJ) {
  Cantilever c = makeCantilever();
  const double T = 1.0 * c.GJ / kLength;  // one radian of twist
  Vec6 w;
  w << 0.0, 0.0, 0.0, T, 0.0, 0.0;
  solveTipLoad(&c, w, 1);
  const Vec3 twist = logSO3(c.state.rotation.back().toRotationMatrix());
  const double expected = T * kLength / c.GJ;
  EXPECT_NEAR(twist.x(), expected, 0.005 * expected);
  std::printf("[ metric   ] torsion: twist error %.2e %%\n",
              100.0 * std::abs(twist.x() - expected) / expected);
  EXPECT_NEAR(c.state.position.back().x(), kLength, 1e-9);
}

}  // namespace
}  // namespace evsim
