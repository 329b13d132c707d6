#include "endovascular_sim/mechanics/beam_element.h"

#include "endovascular_sim/mechanics/so3.h"

namespace evsim {
namespace {

struct ElementKinematics {
  Vec3 phi;    // log(R1^T R2)
  Mat3 Rm;     // mid-rotation frame
  Vec3 chord;  // x2 - x1 [m]
};

ElementKinematics kinematics(const Vec3& x1, const Mat3& R1, const Vec3& x2, const Mat3& R2) {
  ElementKinematics k;
  k.phi = logSO3(R1.transpose() * R2);
  k.Rm = R1 * expSO3(0.5 * k.phi);
  k.chord = x2 - x1;
  return k;
}

}  // namespace

void setBeamElementRestShape(const Vec3& x1, const Mat3& R1, const Vec3& x2, const Mat3& R2,
                             double rest_length, BeamElementRest* rest) {
  const ElementKinematics k = kinematics(x1, R1, x2, R2);
  rest->length = rest_length;
  rest->stretch_shear = k.Rm.transpose() * k.chord / rest_length;
  rest->curvature = k.phi / rest_length;
}

void evaluateBeamElement(const BeamElementRest& rest, const Vec3& x1, const Mat3& R1,
                         const Vec3& x2, const Mat3& R2, bool with_stiffness,
                         BeamElementEval* out) {
  const double L0 = rest.length;
  const ElementKinematics k = kinematics(x1, R1, x2, R2);
  const Mat3 RmT = k.Rm.transpose();

  Vec6& e = out->strain;
  e.head<3>() = RmT * k.chord / L0 - rest.stretch_shear;
  e.tail<3>() = k.phi / L0 - rest.curvature;
  Vec6 c;
  c << rest.stretch_shear_stiffness, rest.bend_twist_stiffness;
  const Vec6 stress = c.cwiseProduct(e);  // section forces [N] and moments [N m]
  out->energy = 0.5 * L0 * e.dot(stress);

  // Strain Jacobian J (6 x 12).
  //   dPhi = P (dth2 - dth1), P = JrInv(Phi) R2^T
  //   dth_m = dth1 + Q (dth2 - dth1), Q = Rm Jr(Phi/2) P / 2
  //   dGamma = Rm^T (dx2 - dx1 + hat(chord) dth_m) / L0
  const Mat3 P = rightJacobianInverse(k.phi) * R2.transpose();
  const Mat3 Q = 0.5 * k.Rm * rightJacobian(0.5 * k.phi) * P;
  const Mat3 G = RmT * hat(k.chord);
  Mat6x12 J;
  J.block<3, 3>(0, 0) = -RmT / L0;
  J.block<3, 3>(0, 3) = G * (Mat3::Identity() - Q) / L0;
  J.block<3, 3>(0, 6) = RmT / L0;
  J.block<3, 3>(0, 9) = G * Q / L0;
  J.block<3, 3>(3, 0).setZero();
  J.block<3, 3>(3, 3) = -P / L0;
  J.block<3, 3>(3, 6).setZero();
  J.block<3, 3>(3, 9) = P / L0;

  out->gradient = L0 * J.transpose() * stress;
  if (with_stiffness) out->stiffness = L0 * J.transpose() * c.asDiagonal() * J;
}

Mat12 beamElementConsistentTangent(const BeamElementRest& rest, const Vec3& x1, const Mat3& R1,
                                   const Vec3& x2, const Mat3& R2) {
  const double hx = 1e-7 * rest.length;  // [m]
  const double hr = 1e-7;                // [rad]
  Mat12 H;
  BeamElementEval plus, minus;
  for (int j = 0; j < 12; ++j) {
    const bool rot = (j / 3) % 2 == 1;
    const double h = rot ? hr : hx;
    Vec3 x1p = x1, x1m = x1, x2p = x2, x2m = x2;
    Mat3 R1p = R1, R1m = R1, R2p = R2, R2m = R2;
    const Vec3 d = h * Vec3::Unit(j % 3);
    switch (j / 3) {
      case 0:
        x1p += d;
        x1m -= d;
        break;
      case 1:
        R1p = expSO3(d) * R1;
        R1m = expSO3(-d) * R1;
        break;
      case 2:
        x2p += d;
        x2m -= d;
        break;
      default:
        R2p = expSO3(d) * R2;
        R2m = expSO3(-d) * R2;
        break;
    }
    evaluateBeamElement(rest, x1p, R1p, x2p, R2p, false, &plus);
    evaluateBeamElement(rest, x1m, R1m, x2m, R2m, false, &minus);
    H.col(j) = (plus.gradient - minus.gradient) / (2.0 * h);
  }
  return 0.5 * (H + H.transpose());
}

}  // namespace evsim
