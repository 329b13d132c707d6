#include "endovascular_sim/geometry/root_finding.h"

#include <cmath>

namespace evsim {
namespace {

SurfacePoint surfaceAt(const ImplicitSurface& field, const Vec3& p, double r,
                       const MotionSnapshot& m) {
  SurfacePoint out;
  out.hit = true;
  out.point = p;
  const Vec3 g = field.evaluate(p, r, m).gradient;
  out.normal = g.norm() > 0.0 ? Vec3(g.normalized()) : Vec3::Zero();
  return out;
}

/// First change of sign of g on p0 + s (p1 - p0), s in (0, 1], from the sign
/// sigma of g(p0), counted only where sigma g < -eps (eps: the penetration
/// tolerance in field units). Certified steps on sigma g + eps >= 0, then
/// bisection of the exact zero between the last point of the start's sign
/// and the first of the other sign.
SurfacePoint firstSignChange(const ImplicitSurface& field, const Vec3& p0, const Vec3& p1, double r,
                             const MotionSnapshot& m, FieldSample at, const RootOptions& options) {
  SurfacePoint none;
  const Vec3 d = p1 - p0;
  const double length = d.norm();
  if (length == 0.0) return none;
  const double sigma = at.value >= 0.0 ? 1.0 : -1.0;
  const double eps = options.penetration_tolerance * at.gradient.norm();
  const double H = field.hessianBound(p0, p1, r) * length * length;
  const double tol_s = options.tolerance / length;
  double s = 0.0, s_same = 0.0, s_other = -1.0;  // last same-sign point, first other-sign after it
  for (int it = 1; it <= options.max_iterations; ++it) {
    const double g = std::max(sigma * at.value + eps, 0.0);
    const double gp = sigma * at.gradient.dot(d);
    // Smallest positive zero of the lower bound g + gp x - H x^2 / 2, in the
    // form that stays accurate as H -> 0 (a plane): 2g / (sqrt(gp^2 + 2Hg) - gp).
    const double den = std::sqrt(gp * gp + 2.0 * H * g) - gp;
    const double step = den > 0.0 ? 2.0 * g / den : 2.0;
    if (s + step >= 1.0) {  // certified to the end: nothing beyond the tolerance
      none.iterations = it;
      return none;
    }
    const double next = std::min(1.0, s + std::max(step, 2.0 * tol_s));
    const FieldSample nf = field.evaluate(p0 + next * d, r, m);
    const double v = sigma * nf.value;
    if (v >= 0.0) {
      s_same = next;
      s_other = -1.0;
    } else if (s_other < 0.0) {
      s_other = next;
    }
    if (v < -eps) {
      double lo = s_same, hi = s_other;
      while (hi - lo > 0.5 * tol_s) {
        const double mid = 0.5 * (lo + hi);
        (sigma * field.evaluate(p0 + mid * d, r, m).value >= 0.0 ? lo : hi) = mid;
      }
      SurfacePoint out = surfaceAt(field, p0 + hi * d, r, m);
      out.s = hi;
      out.iterations = it;
      return out;
    }
    if (next >= 1.0) {
      none.iterations = it;
      return none;  // no penetration beyond the tolerance
    }
    s = next;
    at = nf;
  }
  // Not resolved within the iteration budget: a contact at the last point
  // certified within the tolerance (its gap is then >= -tolerance).
  SurfacePoint out = surfaceAt(field, p0 + s * d, r, m);
  out.s = s;
  out.iterations = options.max_iterations;
  return out;
}

}  // namespace

SurfacePoint firstRoot(const ImplicitSurface& field, const Vec3& p0, const Vec3& p1,
                       double device_radius, const MotionSnapshot& motion,
                       const RootOptions& options) {
  return firstRootFrom(field, p0, field.evaluate(p0, device_radius, motion), p1, device_radius,
                       motion, options);
}

SurfacePoint firstRootFrom(const ImplicitSurface& field, const Vec3& p0, const FieldSample& at,
                           const Vec3& p1, double device_radius, const MotionSnapshot& motion,
                           const RootOptions& options) {
  if (at.value < 0.0) {
    SurfacePoint out = surfaceAt(field, p0, device_radius, motion);
    out.started_outside = true;
    out.s = 0.0;
    return out;
  }
  return firstSignChange(field, p0, p1, device_radius, motion, at, options);
}

SurfacePoint projectToSurface(const ImplicitSurface& field, const Vec3& x, double device_radius,
                              const MotionSnapshot& motion, double max_distance,
                              const RootOptions& options) {
  const FieldSample at = field.evaluate(x, device_radius, motion);
  if (at.gradient.norm() == 0.0) return SurfacePoint{};
  // grad f points into the lumen: outward from inside, inward from outside.
  const Vec3 n = at.gradient.normalized();
  const Vec3 toward = at.value >= 0.0 ? Vec3(-n) : n;
  return firstSignChange(field, x, x + max_distance * toward, device_radius, motion, at, options);
}

}  // namespace evsim
