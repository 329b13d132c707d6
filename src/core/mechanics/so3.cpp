// Rotation group helpers. Declared and documented in
// endovascular_sim/mechanics/so3.h.
#include "endovascular_sim/mechanics/so3.h"

#include <cmath>

namespace evsim {

Mat3 hat(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

Mat3 expSO3(const Vec3& phi) {
  const double theta = phi.norm();
  if (theta < 1e-12) return Mat3::Identity() + hat(phi);
  return Eigen::AngleAxisd(theta, phi / theta).toRotationMatrix();
}

Quat expQuaternion(const Vec3& phi) {
  const double t2 = phi.squaredNorm();
  if (t2 < 1e-8) {  // cos(t/2) and sin(t/2)/t by series: error ~ t^4 / 3840
    const Vec3 v = (0.5 - t2 / 48.0) * phi;
    return Quat(1.0 - t2 / 8.0 + t2 * t2 / 384.0, v.x(), v.y(), v.z());
  }
  const double t = std::sqrt(t2);
  const Vec3 v = (std::sin(0.5 * t) / t) * phi;
  return Quat(std::cos(0.5 * t), v.x(), v.y(), v.z());
}

Vec3 logSO3(const Mat3& R) {
  Quat q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v / q.w();
  return (2.0 * std::atan2(s, q.w()) / s) * v;
}

Mat3 rightJacobian(const Vec3& phi) {
  const double t2 = phi.squaredNorm();
  const Mat3 P = hat(phi);
  double a, b;  // Jr = I - a P + b P^2
  if (t2 < 1e-8) {
    a = 0.5 - t2 / 24.0;
    b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    const double t = std::sqrt(t2);
    a = (1.0 - std::cos(t)) / t2;
    b = (t - std::sin(t)) / (t2 * t);
  }
  return Mat3::Identity() - a * P + b * P * P;
}

Mat3 rightJacobianInverse(const Vec3& phi) {
  const double t2 = phi.squaredNorm();
  const Mat3 P = hat(phi);
  double c;  // JrInv = I + P/2 + c P^2
  if (t2 < 1e-8) {
    c = 1.0 / 12.0 + t2 / 720.0;
  } else {
    const double t = std::sqrt(t2);
    c = 1.0 / t2 - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t));
  }
  return Mat3::Identity() + 0.5 * P + c * P * P;
}

}  // namespace evsim
