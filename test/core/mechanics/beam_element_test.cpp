#include "endovascular_sim/mechanics/beam_element.h"

#include <gtest/gtest.h>

#include "test_helpers.h"

namespace evsim {
namespace {

struct Pose2 {
  Vec3 x1, x2;
  Mat3 R1, R2;
};

double energyOf(const BeamElementRest& rest, const Pose2& p) {
  BeamElementEval ev;
  evaluateBeamElement(rest, p.x1, p.R1, p.x2, p.R2, false, &ev);
  return ev.energy;
}

Vec12 gradientOf(const BeamElementRest& rest, const Pose2& p) {
  BeamElementEval ev;
  evaluateBeamElement(rest, p.x1, p.R1, p.x2, p.R2, false, &ev);
  return ev.gradient;
}

/// Perturbs generalised coordinate j (dx1, dth1, dx2, dth2; world-frame left
/// rotation increments) by h.
Pose2 perturbed(Pose2 p, int j, double h) {
  const Vec3 d = h * Vec3::Unit(j % 3);
  switch (j / 3) {
    case 0:
      p.x1 += d;
      break;
    case 1:
      p.R1 = expSO3(d) * p.R1;
      break;
    case 2:
      p.x2 += d;
      break;
    default:
      p.R2 = expSO3(d) * p.R2;
      break;
  }
  return p;
}

/// A pre-curved, twisted rest element of length 2 mm.
BeamElementRest curvedRest(Pose2* rest_pose) {
  const double L = 2e-3;
  const Vec3 kappa(40.0, -120.0, 250.0);  // [1/m]
  rest_pose->x1 = Vec3(0.01, -0.02, 0.03);
  rest_pose->R1 = expSO3(Vec3(0.2, 0.4, -0.3));
  rest_pose->R2 = rest_pose->R1 * expSO3(kappa * L);
  rest_pose->x2 = rest_pose->x1 + rest_pose->R1 * expSO3(0.5 * kappa * L) * Vec3::UnitX() * L;
  BeamElementRest rest;
  setBeamElementRestShape(rest_pose->x1, rest_pose->R1, rest_pose->x2, rest_pose->R2, L, &rest);
  const BeamSection s = test::wireSection(60e9, 2e-4);
  rest.stretch_shear_stiffness = s.stretchShearStiffness();
  rest.bend_twist_stiffness = s.bendTwistStiffness();
  return rest;
}

TEST(BeamElement, GradientMatchesFiniteDifferencesOfEnergy) {
  Pose2 p;
  const BeamElementRest rest = curvedRest(&p);
  std::mt19937 rng(7);
  p.x2 += Vec3(1e-4, -2e-4, 5e-5);
  p.R2 = expSO3(Vec3(0.3, -0.5, 0.2)) * p.R2;
  p.R1 = expSO3(Vec3(-0.1, 0.2, 0.6)) * p.R1;
  const Vec12 g = gradientOf(rest, p);
  for (int j = 0; j < 12; ++j) {
    const double h = (j / 3) % 2 == 0 ? 1e-9 : 1e-7;
    const double fd =
        (energyOf(rest, perturbed(p, j, h)) - energyOf(rest, perturbed(p, j, -h))) / (2.0 * h);
    EXPECT_NEAR(g(j), fd, 1e-5 * g.cwiseAbs().maxCoeff()) << "coordinate " << j;
  }
}

TEST(BeamElement, RigidMotionOfPreShapedElementCostsNothing) {
  Pose2 p;
  const BeamElementRest rest = curvedRest(&p);
  std::mt19937 rng(3);
  for (int k = 0; k < 50; ++k) {
    const Mat3 R = test::randomRotation(&rng);
    const Vec3 t(0.1 * k, -0.3, 0.7);
    Pose2 q{R * p.x1 + t, R * p.x2 + t, R * p.R1, R * p.R2};
    BeamElementEval ev;
    evaluateBeamElement(rest, q.x1, q.R1, q.x2, q.R2, true, &ev);
    EXPECT_LT(ev.energy, 1e-18);
    EXPECT_LT(ev.gradient.norm(), 1e-6);  // forces ~ EA * 1e-13 strain
  }
}

// At rest the Gauss-Newton tangent is the exact Hessian: compare with finite
// differences of the (independently checked) gradient.
TEST(BeamElement, TangentAtRestEqualsHessian) {
  Pose2 p;
  const BeamElementRest rest = curvedRest(&p);
  BeamElementEval ev;
  evaluateBeamElement(rest, p.x1, p.R1, p.x2, p.R2, true, &ev);
  for (int j = 0; j < 12; ++j) {
    const double h = (j / 3) % 2 == 0 ? 1e-9 : 1e-7;
    const Vec12 fd =
        (gradientOf(rest, perturbed(p, j, h)) - gradientOf(rest, perturbed(p, j, -h))) / (2.0 * h);
    EXPECT_LT((fd - ev.stiffness.col(j)).norm(), 1e-4 * ev.stiffness.norm()) << "column " << j;
  }
}

// Away from rest the tangent is the Gauss-Newton part L0 J^T C J: compare
// with J formed by finite differences of the strain, a second way to the
// same matrix (the element forms it from 3x3 blocks).
TEST(BeamElement, TangentIsGaussNewtonOfStrainJacobian) {
  Pose2 p;
  const BeamElementRest rest = curvedRest(&p);
  p.x2 += Vec3(2e-5, -4e-5, 1e-5);
  p.R2 = expSO3(Vec3(0.05, -0.08, 0.03)) * p.R2;
  p.R1 = expSO3(Vec3(-0.02, 0.04, 0.07)) * p.R1;
  BeamElementEval ev;
  evaluateBeamElement(rest, p.x1, p.R1, p.x2, p.R2, true, &ev);
  Mat6x12 J;
  for (int j = 0; j < 12; ++j) {
    const double h = (j / 3) % 2 == 0 ? 1e-9 : 1e-7;
    BeamElementEval plus, minus;
    const Pose2 pp = perturbed(p, j, h), pm = perturbed(p, j, -h);
    evaluateBeamElement(rest, pp.x1, pp.R1, pp.x2, pp.R2, false, &plus);
    evaluateBeamElement(rest, pm.x1, pm.R1, pm.x2, pm.R2, false, &minus);
    J.col(j) = (plus.strain - minus.strain) / (2.0 * h);
  }
  Vec6 c;
  c << rest.stretch_shear_stiffness, rest.bend_twist_stiffness;
  const Mat12 K = rest.length * J.transpose() * c.asDiagonal() * J;
  EXPECT_LT((K - ev.stiffness).norm(), 1e-5 * K.norm());
  EXPECT_LT((ev.stiffness - ev.stiffness.transpose()).norm(), 1e-12 * K.norm());
}

// The quaternion and rotation-matrix forms of the element agree, also at a
// relative rotation of nearly pi and at none.
TEST(BeamElement, QuaternionAndMatrixFormsAgree) {
  Pose2 p;
  const BeamElementRest rest = curvedRest(&p);
  for (const Vec3& turn :
       {Vec3(0, 0, 0), Vec3(1e-9, 0, 0), Vec3(0.3, -0.2, 0.1), Vec3(0, 3.1, 0)}) {
    const Mat3 R2 = expSO3(turn) * p.R1;
    BeamElementEval m, q;
    evaluateBeamElement(rest, p.x1, p.R1, p.x2, R2, true, &m);
    evaluateBeamElement(rest, p.x1, Quat(p.R1), p.x2, Quat(R2), true, &q);
    EXPECT_LT((m.gradient - q.gradient).norm(), 1e-12 * (1.0 + m.gradient.norm()));
    EXPECT_LT((m.stiffness - q.stiffness).norm(), 1e-12 * m.stiffness.norm());
    // Phi from the quaternion equals log(R1^T R2).
    EXPECT_LT(
        (q.strain.tail<3>() + rest.curvature - logSO3(p.R1.transpose() * R2) / rest.length).norm(),
        1e-9);
  }
}

}  // namespace
}  // namespace evsim
