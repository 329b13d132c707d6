#include "endovascular_sim/mechanics/so3.h"

#include <gtest/gtest.h>

#include <random>

namespace evsim {
namespace {

TEST(So3, LogInvertsExpUpToPi) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 1000; ++k) {
    Vec3 axis(u(rng), u(rng), u(rng));
    axis.normalize();
    const double angle = 3.1 * std::abs(u(rng)) + 1e-14;
    const Vec3 phi = angle * axis;
    EXPECT_LT((logSO3(expSO3(phi)) - phi).norm(), 1e-10 * std::max(1.0, angle));
  }
}

TEST(So3, ExpMatchesEigenAngleAxis) {
  const Vec3 phi(0.3, -1.2, 0.7);
  const Mat3 ref = Eigen::AngleAxisd(phi.norm(), phi.normalized()).toRotationMatrix();
  EXPECT_LT((expSO3(phi) - ref).norm(), 1e-14);
}

TEST(So3, QuaternionExpMatchesEigenAngleAxis) {
  for (double angle : {0.0, 1e-12, 1e-6, 9.9e-5, 1.01e-4, 0.01, 1.0, 3.1}) {
    const Vec3 axis = Vec3(0.3, -1.2, 0.7).normalized();
    const Quat q = expQuaternion(angle * axis);
    const Mat3 ref = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    EXPECT_LT((q.toRotationMatrix() - ref).norm(), 1e-15 + 1e-15 * angle) << angle;
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  }
}

// Jr is defined by exp(phi + d) = exp(phi) exp(Jr d) + O(d^2): check by finite
// differences of the exponential, and JrInv as its matrix inverse.
TEST(So3, RightJacobianMatchesFiniteDifferences) {
  for (const Vec3& phi : {Vec3(0.3, -1.2, 0.7), Vec3(1e-5, 2e-5, 0.0), Vec3(0.0, 0.0, 3.0)}) {
    const double h = 1e-6;
    const Mat3 Jr = rightJacobian(phi);
    for (int j = 0; j < 3; ++j) {
      const Vec3 d = h * Vec3::Unit(j);
      const Vec3 fd = (logSO3(expSO3(phi).transpose() * expSO3(phi + d)) -
                       logSO3(expSO3(phi).transpose() * expSO3(phi - d))) /
                      (2.0 * h);
      EXPECT_LT((fd - Jr.col(j)).norm(), 1e-8);
    }
    EXPECT_LT((rightJacobianInverse(phi) * Jr - Mat3::Identity()).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace evsim
