// Collision detection on the implicit surface (section 2.3 of the paper).
// Declared and documented in endovascular_sim/geometry/root_finding.h.
#include "endovascular_sim/geometry/root_finding.h"

#include <algorithm>
#include <cmath>

namespace evsim {
namespace {

/// A hit at p, where the field's gradient is g.
SurfacePoint hitAt(const Vec3& p, const Vec3& g) {
  SurfacePoint out;
  out.hit = true;
  out.point = p;
  out.normal = g.norm() > 0.0 ? Vec3(g.normalized()) : Vec3::Zero();
  return out;
}

SurfacePoint surfaceAt(const ImplicitSurface& field, const Vec3& p, double r,
                       const MotionSnapshot& m) {
  return hitAt(p, field.evaluate(p, r, m).gradient);
}

/// The first point of the other sign of the zero of g bracketed on p0 + s d
/// by lo (sigma g = g_lo >= 0) and hi (sigma g = g_hi < 0), within a bracket
/// of width `width`: the Illinois variant of regula falsi (superlinear; a
/// retained end has its value halved, so both ends close in), each trial
/// kept a quarter width inside the bracket so that the bracket shrinks by
/// at least that much. About 6-10 evaluations where bisection took 30.
/// *at_hi: the field at hi on entry, and at the returned end on return
/// (whose gradient is the hit's normal: no evaluation more).
double bracketedZero(const ImplicitSurface& field, const Vec3& p0, const Vec3& d, double r,
                     const MotionSnapshot& m, double sigma, double lo, double g_lo, double hi,
                     double g_hi, double width, FieldSample* at_hi) {
  int replaced = 0;  // the end the last trial replaced: -1 lo, +1 hi
  while (hi - lo > width) {
    double mid = g_lo - g_hi > 0.0 ? lo + (hi - lo) * g_lo / (g_lo - g_hi) : 0.5 * (lo + hi);
    mid = std::clamp(mid, lo + 0.25 * width, hi - 0.25 * width);
    const FieldSample f = field.evaluate(p0 + mid * d, r, m);
    const double v = sigma * f.value;

    if (v >= 0.0) {
      lo = mid;
      g_lo = v;
      if (replaced < 0) g_hi *= 0.5;  // hi kept twice in a row
      replaced = -1;
    } else {
      hi = mid;
      g_hi = v;
      *at_hi = f;
      if (replaced > 0) g_lo *= 0.5;  // lo kept twice in a row
      replaced = 1;
    }
  }
  return hi;
}

/// First change of sign of g on p0 + s (p1 - p0), s in (0, 1], from the sign
/// sigma of g(p0), counted only where sigma g < -eps (eps: the crossing
/// depth in field units). Certified steps on sigma g + eps >= 0, then
/// bracketing of the exact zero between the last point of the start's sign
/// and the first of the other sign. With the field at p1 known (`end`), the
/// path is also certified from that end: backwards from p1 by the same
/// lower bound, and at once where the chord bound min(g0, g1) - H / 8
/// (H: the Hessian bound times |p1 - p0|^2) stays positive.
SurfacePoint firstSignChange(const ImplicitSurface& field, const Vec3& p0, const Vec3& p1, double r,
                             const MotionSnapshot& m, FieldSample at, const FieldSample* end,
                             const RootOptions& options) {
  SurfacePoint none;
  const Vec3 d = p1 - p0;
  const double length = d.norm();
  if (length == 0.0) return none;
  const double sigma = at.value >= 0.0 ? 1.0 : -1.0;
  const double eps = options.crossing_depth * at.gradient.norm();
  const double H = field.hessianBound(p0, p1, r) * length * length;
  const double tol_s = options.tolerance / length;
  // The part (s_end, 1] certified from the end, when it is on the start's side.
  double s_end = 1.0;
  if (end && sigma * end->value + eps >= 0.0) {
    const double g0 = sigma * at.value + eps, g1 = sigma * end->value + eps;
    if (std::min(g0, g1) >= 0.125 * H) {  // the chord bound: inside throughout
      none.iterations = 0;
      return none;
    }
    const double gp1 = sigma * end->gradient.dot(d);  // slope at p1 along the path
    const double den = std::sqrt(gp1 * gp1 + 2.0 * H * g1) + gp1;
    s_end = den > 0.0 ? 1.0 - 2.0 * g1 / den : -1.0;
  }
  double s = 0.0, s_same = 0.0, s_other = -1.0;  // last same-sign point, first other-sign after it
  double g_same = std::max(sigma * at.value, 0.0), g_other = 0.0;  // sigma g there
  FieldSample at_other;                                            // the field at s_other
  for (int it = 1; it <= options.max_iterations; ++it) {
    const double g = std::max(sigma * at.value + eps, 0.0);
    const double gp = sigma * at.gradient.dot(d);
    // Smallest positive zero of the lower bound g + gp x - H x^2 / 2, in the
    // form that stays accurate as H -> 0 (a plane): 2g / (sqrt(gp^2 + 2Hg) - gp).
    const double den = std::sqrt(gp * gp + 2.0 * H * g) - gp;
    const double step = den > 0.0 ? 2.0 * g / den : 2.0;
    if (s + step >= std::min(1.0, s_end)) {  // certified to the end: nothing beyond the tolerance
      none.iterations = it;
      return none;
    }
    const double next = std::min(1.0, s + std::max(step, 2.0 * tol_s));
    const FieldSample nf = field.evaluate(p0 + next * d, r, m);
    const double v = sigma * nf.value;
    if (v >= 0.0) {
      s_same = next;
      g_same = v;
      s_other = -1.0;
    } else if (s_other < 0.0) {
      s_other = next;
      g_other = v;
      at_other = nf;
    }
    if (v < -eps) {
      const double hi = bracketedZero(field, p0, d, r, m, sigma, s_same, g_same, s_other, g_other,
                                      0.5 * tol_s, &at_other);
      SurfacePoint out = hitAt(p0 + hi * d, at_other.gradient);
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

/// The surface along x + t u from x (u unit, toward the surface: the
/// field's sign at x, sigma, times g falls along it at the rate |grad g|),
/// by Newton's method where it is certified: on [0, t_max] the slope of
/// f = sigma g stays below -(|grad g(x)| - H t_max) < 0 (H: the Hessian
/// bound over that stretch), so f has at most one zero there, the first
/// along the way, and a point with f < 0 has it within |f| / that rate
/// behind. Returns the first point of the other sign within the tolerance
/// of the zero, its normal from the gradient there, as firstSignChange does;
/// hit false when an iterate would leave [0, t_max] or after a few steps
/// (the caller then searches with certified steps). t_max is three Newton
/// steps from x: a point a few micrometres from the wall (a kept contact's,
/// an update's) reaches it in two or three evaluations, where the certified
/// steps and the bracketing took five or six.
SurfacePoint newtonToSurface(const ImplicitSurface& field, const Vec3& x, const FieldSample& at,
                             const Vec3& u, double max_distance, double r, const MotionSnapshot& m,
                             const RootOptions& options) {
  constexpr int kMaxSteps = 4;
  SurfacePoint none;
  const double sigma = at.value >= 0.0 ? 1.0 : -1.0;
  const double rate0 = at.gradient.norm();
  const double tol = options.tolerance;
  const double t_max = std::min(max_distance, 3.0 * std::abs(at.value) / rate0 + 4.0 * tol);
  const double min_rate = rate0 - field.hessianBound(x, x + t_max * u, r) * t_max;
  if (!(min_rate > 0.0)) return none;
  double t = 0.0, f = sigma * at.value, rate = rate0;
  for (int it = 1; it <= kMaxSteps; ++it) {
    // Aimed a little past the zero (a quarter of the tolerance, or the
    // crossing depth if smaller), so that the answer lies on the other
    // side, as a bracket's end would.
    const double next = t + f / rate + std::min(0.25 * tol, options.crossing_depth);
    if (!(next >= 0.0 && next <= t_max)) return none;
    const FieldSample g = field.evaluate(x + next * u, r, m);
    t = next;
    f = sigma * g.value;
    rate = -sigma * g.gradient.dot(u);
    if (f < 0.0 && -f / min_rate <= tol) {
      SurfacePoint out = hitAt(x + t * u, g.gradient);
      out.s = t / max_distance;
      out.iterations = it;
      return out;
    }
    if (!(rate > 0.0)) return none;
  }
  return none;
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
  return firstSignChange(field, p0, p1, device_radius, motion, at, nullptr, options);
}

SurfacePoint firstRootBetween(const ImplicitSurface& field, const Vec3& p0, const FieldSample& at,
                              const Vec3& p1, const FieldSample& at_end, double device_radius,
                              const MotionSnapshot& motion, const RootOptions& options) {
  if (at.value < 0.0) return firstRootFrom(field, p0, at, p1, device_radius, motion, options);
  return firstSignChange(field, p0, p1, device_radius, motion, at, &at_end, options);
}

SurfacePoint projectToSurface(const ImplicitSurface& field, const Vec3& x, double device_radius,
                              const MotionSnapshot& motion, double max_distance,
                              const RootOptions& options) {
  return projectToSurfaceFrom(field, x, field.evaluate(x, device_radius, motion), device_radius,
                              motion, max_distance, options);
}

SurfacePoint projectToSurfaceFrom(const ImplicitSurface& field, const Vec3& x,
                                  const FieldSample& at, double device_radius,
                                  const MotionSnapshot& motion, double max_distance,
                                  const RootOptions& options) {
  if (at.gradient.norm() == 0.0) return SurfacePoint{};
  // grad f points into the lumen: outward from inside, inward from outside.
  const Vec3 n = at.gradient.normalized();
  const Vec3 toward = at.value >= 0.0 ? Vec3(-n) : n;
  const SurfacePoint near =
      newtonToSurface(field, x, at, toward, max_distance, device_radius, motion, options);
  if (near.hit) return near;
  return firstSignChange(field, x, x + max_distance * toward, device_radius, motion, at, nullptr,
                         options);
}

}  // namespace evsim
