// Co-rotational Timoshenko beam element with two 6-DOF nodes. Declared and
// documented in endovascular_sim/mechanics/beam_element.h.
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
  evaluateBeamElement(rest, x1, Quat(R1), x2, Quat(R2), with_stiffness, out);
}

// One function of about 85 lines: strain, gradient and tangent share the
// blocks (Rm, P, Q, G) of one derivation; split, each part would recompute or
// pass them all.
void evaluateBeamElement(const BeamElementRest& rest, const Vec3& x1, const Quat& q1,
                         const Vec3& x2, const Quat& q2, bool with_stiffness,
                         BeamElementEval* out) {
  const double L0 = rest.length;
  // Relative rotation q = q1^* q2 = (cos(t/2), sin(t/2) axis), the shortest
  // way round; Phi = t axis. Its half rotation exp(Phi/2) is (1 + q)/|1 + q|
  // and the trigonometric functions of t and t/2 below come from w and s,
  // so that the element needs one atan2 and no sin or cos.
  Quat qr = q1.conjugate() * q2;
  if (qr.w() < 0.0) qr.coeffs() = -qr.coeffs();
  qr.normalize();
  const double w = qr.w(), s = qr.vec().norm();  // cos(t/2), sin(t/2)
  const double t = 2.0 * std::atan2(s, w);       // |Phi| [rad]
  const Vec3 phi = s > 1e-300 ? Vec3((t / s) * qr.vec()) : Vec3(2.0 * qr.vec());
  Quat half(1.0 + w, qr.x(), qr.y(), qr.z());
  half.normalize();
  const Mat3 Rm = (q1 * half).toRotationMatrix();
  const Mat3 RmT = Rm.transpose();
  const Vec3 chord = x2 - x1;

  Vec6& e = out->strain;
  e.head<3>() = RmT * chord / L0 - rest.stretch_shear;
  e.tail<3>() = phi / L0 - rest.curvature;
  const Vec3& cs = rest.stretch_shear_stiffness;
  const Vec3& cb = rest.bend_twist_stiffness;
  const Vec3 sigma_s = cs.cwiseProduct(e.head<3>());  // section forces [N]
  const Vec3 sigma_b = cb.cwiseProduct(e.tail<3>());  // section moments [N m]
  out->energy = 0.5 * L0 * (e.head<3>().dot(sigma_s) + e.tail<3>().dot(sigma_b));

  // Strain Jacobian J (6 x 12), in 3x3 blocks:
  //   dPhi = P (dth2 - dth1), P = JrInv(Phi) R2^T
  //   dth_m = dth1 + Q (dth2 - dth1), Q = Rm Jr(Phi/2) P / 2
  //   dGamma = Rm^T (dx2 - dx1 + hat(chord) dth_m) / L0
  // so that L0 J = [-Rm^T, G - GQ, Rm^T, GQ; 0, -P, 0, P], G = Rm^T hat(chord).
  // JrInv(Phi) = I + hat/2 + c hat^2, c = 1/t^2 - (1 + cos t)/(2 t sin t)
  //   = 1/t^2 - w/(2 t s); Jr(Phi/2) = I - a hat + b hat^2 (of Phi/2, angle
  //   u = t/2): a = (1 - cos u)/u^2 = s^2/((1 + w) u^2), b = (u - sin u)/u^3.
  const double t2 = t * t, u = 0.5 * t, u2 = u * u;
  const double c = t2 < 1e-8 ? 1.0 / 12.0 + t2 / 720.0 : 1.0 / t2 - w / (2.0 * t * s);
  const double a = u2 < 1e-300 ? 0.5 : s * s / ((1.0 + w) * u2);
  const double b = u < 1e-2 ? 1.0 / 6.0 - u2 / 120.0 + u2 * u2 / 5040.0 - u2 * u2 * u2 / 362880.0
                            : (u - s) / (u2 * u);
  const Mat3 hp = hat(phi), hp2 = hp * hp;
  const Mat3 P = (Mat3::Identity() + 0.5 * hp + c * hp2) * q2.toRotationMatrix().transpose();
  const Mat3 Q = 0.5 * Rm * (Mat3::Identity() - (0.5 * a) * hp + (0.25 * b) * hp2) * P;
  const Mat3 G = RmT * hat(chord);
  const Mat3 GQ = G * Q;

  // Gradient L0 J^T sigma: forces and world moments on the nodes.
  const Vec3 f = Rm * sigma_s;  // on node 2; node 1 gets -f
  const Vec3 u_s = G.transpose() * sigma_s;
  const Vec3 Qu = Q.transpose() * u_s;
  const Vec3 Pm = P.transpose() * sigma_b;
  out->gradient.segment<3>(0) = -f;
  out->gradient.segment<3>(3) = u_s - Qu - Pm;
  out->gradient.segment<3>(6) = f;
  out->gradient.segment<3>(9) = Qu + Pm;
  if (!with_stiffness) return;

  // Gauss-Newton tangent L0 J^T C J from the blocks (B1 = G - GQ, B2 = GQ).
  const Mat3 B1 = G - GQ;
  const Mat3 CsB1 = cs.asDiagonal() * B1, CsB2 = cs.asDiagonal() * GQ;
  const Mat3 S = Rm * cs.asDiagonal() * RmT / L0;
  const Mat3 T1 = Rm * CsB1 / L0, T2 = Rm * CsB2 / L0;
  const Mat3 PCP = P.transpose() * cb.asDiagonal() * P / L0;
  Mat12& K = out->stiffness;
  K.block<3, 3>(0, 0) = S;
  K.block<3, 3>(0, 3) = -T1;
  K.block<3, 3>(0, 6) = -S;
  K.block<3, 3>(0, 9) = -T2;
  K.block<3, 3>(3, 3) = B1.transpose() * CsB1 / L0 + PCP;
  K.block<3, 3>(3, 6) = T1.transpose();
  K.block<3, 3>(3, 9) = B1.transpose() * CsB2 / L0 - PCP;
  K.block<3, 3>(6, 6) = S;
  K.block<3, 3>(6, 9) = T2;
  K.block<3, 3>(9, 9) = GQ.transpose() * CsB2 / L0 + PCP;
  K.block<3, 3>(3, 0) = -T1.transpose();
  K.block<3, 3>(6, 0) = -S;
  K.block<3, 3>(6, 3) = T1;
  K.block<3, 3>(9, 0) = -T2.transpose();
  K.block<3, 3>(9, 3) = K.block<3, 3>(3, 9).transpose();
  K.block<3, 3>(9, 6) = T2.transpose();
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
