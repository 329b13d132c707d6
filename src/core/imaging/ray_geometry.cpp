// Where a ray runs inside simple solids: the exact intervals the X-ray
// projection integrates over (devices as cylinders, the body as an elliptic
// cylinder, the vessels' bounding capsules). Declared and documented in
// endovascular_sim/imaging/ray_geometry.h.
#include "endovascular_sim/imaging/ray_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evsim {

namespace {

/// Roots of a t^2 + 2 b t + c <= 0 as an interval (a >= 0).
RayInterval quadraticInside(double a, double b, double c) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (a < 1e-300) return c <= 0.0 ? RayInterval{-kInf, kInf} : RayInterval{};
  const double disc = b * b - a * c;
  if (disc <= 0.0) return {};
  const double root = std::sqrt(disc);
  // The stable pair: q = -(b + sign(b) root), t = q / a and c / q.
  const double q = -(b + std::copysign(root, b));
  double t0 = q / a, t1 = q != 0.0 ? c / q : -t0;
  if (t0 > t1) std::swap(t0, t1);
  return {t0, t1};
}

}  // namespace

RayInterval rayInCylinder(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& u, double r,
                          double s0, double s1) {
  const Vec3 w = o - a;
  const double du = d.dot(u), wu = w.dot(u);
  const Vec3 dp = d - du * u, wp = w - wu * u;  // across the axis
  RayInterval in = quadraticInside(dp.squaredNorm(), dp.dot(wp), wp.squaredNorm() - r * r);
  if (in.empty()) return in;
  // The slab s0 <= wu + t du <= s1.
  if (std::abs(du) < 1e-300) {
    if (wu < s0 || wu > s1) return {};
  } else {
    double ta = (s0 - wu) / du, tb = (s1 - wu) / du;
    if (ta > tb) std::swap(ta, tb);
    in.t0 = std::max(in.t0, ta);
    in.t1 = std::min(in.t1, tb);
  }
  return in;
}

RayInterval rayInEllipticCylinder(const Vec3& o, const Vec3& d, const Vec3& c, const Vec3& axis,
                                  const Vec3& e, double ea, double eb) {
  if (!(ea > 0.0 && eb > 0.0)) return {};
  const Vec3 f = axis.cross(e);
  const Vec3 w = o - c;
  const double px = w.dot(e) / ea, py = w.dot(f) / eb;
  const double dx = d.dot(e) / ea, dy = d.dot(f) / eb;
  return quadraticInside(dx * dx + dy * dy, px * dx + py * dy, px * px + py * py - 1.0);
}

}  // namespace evsim
