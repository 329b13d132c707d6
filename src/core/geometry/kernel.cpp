// The convolution kernel of the vessel surface and its closed-form integrals.
// Declared and documented in endovascular_sim/geometry/kernel.h.
#include "endovascular_sim/geometry/kernel.h"

#include <algorithm>
#include <cmath>

namespace evsim {

double isoValueForAlpha(double alpha) { return 32.0 / 35.0 * std::pow(1.0 - alpha * alpha, 3.5); }

void addSegmentField(const Vec3& a, const Vec3& b, double R, const Vec3& p, FieldSample* out) {
  const Vec3 ab = b - a;
  const double L = ab.norm();
  if (L <= 0.0) return;
  addSegmentFieldAlong(a, ab / L, L, R, p, out);
}

void addSegmentFieldAlong(const Vec3& a, const Vec3& u, double L, double R, const Vec3& p,
                          FieldSample* out) {
  const Vec3 w = p - a;
  const double t0 = w.dot(u);
  const Vec3 perp = w - t0 * u;  // from the line to p
  const double q = 1.0 / (R * R);
  const double c = 1.0 - perp.squaredNorm() * q;
  if (c <= 0.0) return;
  const double h = R * std::sqrt(c);
  const double lo = std::max(-t0, -h), hi = std::min(L - t0, h);
  if (lo >= hi) return;
  // Antiderivatives in s = t - t0 of (c - q s^2)^3, (c - q s^2)^2 and s (c - q s^2)^2.
  const double c2 = c * c, q2 = q * q;
  auto I0 = [&](double s) {
    const double s2 = s * s;
    return s * (c2 * c - s2 * (c2 * q - s2 * (0.6 * c * q2 - s2 * q2 * q / 7.0)));
  };
  auto J0 = [&](double s) {
    const double s2 = s * s;
    return s * (c2 - s2 * (2.0 / 3.0 * c * q - 0.2 * q2 * s2));
  };
  auto J1 = [&](double s) {
    const double v = c - q * s * s;
    return -v * v * v / (6.0 * q);
  };
  out->value += (I0(hi) - I0(lo)) / R;
  const double k = -6.0 * q / R;
  out->gradient += k * ((J0(hi) - J0(lo)) * perp - (J1(hi) - J1(lo)) * u);
}

void addSphereField(const Vec3& c, double R, double weight, const Vec3& p, FieldSample* out) {
  const Vec3 d = p - c;
  const double q = 1.0 / (R * R);
  const double v = 1.0 - d.squaredNorm() * q;
  if (v <= 0.0) return;
  out->value += weight * v * v * v;
  out->gradient += weight * (-6.0 * q * v * v) * d;
}

// Hessian of K_R at distance r: -6q(1-qr^2)^2 I + 24 q^2 (1-qr^2) d d^T, whose
// norm is at most 6q + 24 q^2 r^2 (1 - q r^2) <= 12 q. A segment integrates it
// over a length of at most 2R and divides by R: 24 q.
double segmentHessianBound(double R) { return 24.0 / (R * R); }

double sphereHessianBound(double R, double weight) { return 12.0 * weight / (R * R); }

}  // namespace evsim
