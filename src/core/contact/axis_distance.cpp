// Distances between two device elements' axes, and where two moving axes
// first touch (the effect 'device_contact'; internal to the contact solver).
// Declared and documented in device_pairs.h.
#include <algorithm>
#include <cmath>

#include "device_pairs.h"

namespace evsim {
namespace pairs {

namespace {

/// The parameters in [0, 1]^2 of the closest points of segments p0 p1 and
/// q0 q1 (Ericson, Real-Time Collision Detection, 5.1.9).
void closestOnSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, double* s,
                       double* t) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  *s = *t = 0.0;
  if (!(a > 0.0) && !(e > 0.0)) return;
  if (!(a > 0.0)) {
    *t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = d1.dot(r);
  if (!(e > 0.0)) {
    *s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = d1.dot(d2), denominator = a * e - b * b;
  *s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  *t = (b * *s + f) / e;
  if (*t < 0.0) {
    *t = 0.0;
    *s = std::clamp(-c / a, 0.0, 1.0);
  } else if (*t > 1.0) {
    *t = 1.0;
    *s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

}  // namespace

Eigen::AlignedBox3d axisBox(const DeviceModel& model, const DeviceState& x, int e) {
  const double bow = HermiteAxis::of(model, x, e).bow();
  Eigen::AlignedBox3d box(x.position[e]);
  box.extend(x.position[e + 1]);
  return Eigen::AlignedBox3d(box.min().array() - bow, box.max().array() + bow);
}

double closestAxisPoints(const HermiteAxis& axis_a, const HermiteAxis& axis_b, double* xi_a,
                         double* xi_b) {
  closestOnSegments(axis_a.p0, axis_a.p1, axis_b.p0, axis_b.p1, xi_a, xi_b);
  const AxisCubic a(axis_a), b(axis_b);  // (Newton's evaluations)
  // The axes bow off their chords (a coil's element by about L^2 kappa / 8):
  // Newton on f = |p_a(xi_a) - p_b(xi_b)|^2 / 2 in both parameters from the
  // chords' answer, kept in [0, 1]^2; a parameter on its bound gets the
  // other's best for it; where the Hessian is singular (the axes parallel
  // there: a coil's touching turns) one round of one-dimensional steps, as
  // the distance hardly changes along them.
  for (int it = 0; it < 12; ++it) {
    const AxisPoint pa = a.at(*xi_a), pb = b.at(*xi_b);
    const Vec3 r = pa.position - pb.position;
    const double ga = pa.first.dot(r), gb = -pb.first.dot(r);
    const double haa = pa.second.dot(r) + pa.first.squaredNorm();
    const double hbb = -pb.second.dot(r) + pb.first.squaredNorm();
    const double hab = -pa.first.dot(pb.first);
    const double det = haa * hbb - hab * hab;
    double na, nb;
    if (det > 1e-9 * haa * hbb && haa > 0.0) {
      na = std::clamp(*xi_a - (hbb * ga - hab * gb) / det, 0.0, 1.0);
      nb = std::clamp(*xi_b - (haa * gb - hab * ga) / det, 0.0, 1.0);
      const bool clamped = na == 0.0 || na == 1.0 || nb == 0.0 || nb == 1.0;
      if (clamped) {  // the other parameter's best for the clamped one
        if (na == 0.0 || na == 1.0) nb = b.closestParameter(a.position(na), nb);
        if (nb == 0.0 || nb == 1.0) na = a.closestParameter(b.position(nb), na);
      }
    } else {  // parallel there: the distance hardly changes along them, one round
      na = a.closestParameter(pb.position, *xi_a);
      nb = b.closestParameter(a.position(na), *xi_b);
      *xi_a = na, *xi_b = nb;
      break;
    }
    // Settled once a step moves neither parameter by 1e-10: Newton's next
    // error is about the square of that step (1e-20 of the element).
    const bool settled = std::abs(na - *xi_a) < 1e-10 && std::abs(nb - *xi_b) < 1e-10;
    *xi_a = na, *xi_b = nb;
    if (settled) break;
  }
  return (a.position(*xi_a) - b.position(*xi_b)).norm();
}

double closestAxisPoints(const DeviceModel& ma, const DeviceState& xa, int ea,
                         const DeviceModel& mb, const DeviceState& xb, int eb, double* xi_a,
                         double* xi_b) {
  return closestAxisPoints(HermiteAxis::of(ma, xa, ea), HermiteAxis::of(mb, xb, eb), xi_a, xi_b);
}

double axisGapBound(const HermiteAxis& a, double bow_a, const HermiteAxis& b, double bow_b) {
  double s = 0.0, t = 0.0;
  closestOnSegments(a.p0, a.p1, b.p0, b.p1, &s, &t);
  const Vec3 across = a.p0 + s * (a.p1 - a.p0) - (b.p0 + t * (b.p1 - b.p0));
  const double chords = across.norm();
  const double bound = chords - bow_a - bow_b;
  if (!(chords > 0.0)) return bound;
  const Vec3 n = across / chords;
  const double a0 = n.dot(a.p0), a1 = n.dot(a.p1), b0 = n.dot(b.p0), b1 = n.dot(b.p1);
  const double a_low = std::min({a0, a1, a0 + n.dot(a.m0) / 3.0, a1 - n.dot(a.m1) / 3.0});
  const double b_high = std::max({b0, b1, b0 + n.dot(b.m0) / 3.0, b1 - n.dot(b.m1) / 3.0});
  return std::max(bound, a_low - b_high);
}

StartAxes::StartAxes(const std::vector<DeviceModel>& devices, const std::vector<DeviceState>& x)
    : devices_(&devices), x_(&x), axis_(devices.size()), bow_(devices.size()) {
  for (size_t d = 0; d < devices.size(); ++d) {
    axis_[d].reset(new HermiteAxis[devices[d].num_nodes - 1]);
    bow_[d].assign(devices[d].num_nodes - 1, -1.0);
  }
}

const HermiteAxis& StartAxes::axis(int d, int e) const {
  if (bow_[d][e] < 0.0) {
    axis_[d][e] = HermiteAxis::of((*devices_)[d], (*x_)[d], e);
    bow_[d][e] = axis_[d][e].bow();
  }
  return axis_[d][e];
}

double StartAxes::bow(int d, int e) const {
  axis(d, e);
  return bow_[d][e];
}

/// Conservative advancement: on the path, every point of axis a moves at
/// most `speed` (ElementRef::sweep of both) per unit of s relative to every
/// point of axis b, so the axes' distance d(s) changes no faster, and a step
/// of (d(s) - radii) / speed cannot pass a touch. Stops where d <= radii
/// (1 + 1 %), or at s = 1; after 64 advances (a near miss: the axes slide
/// by within a percent of touching) it answers where it stopped, with that
/// place's normal. Where the distance is a few millionths of the radii (the
/// axes met), the normal across both axes (pairNormal).
Touch firstTouch(const HermiteAxis& a0, const HermiteAxis& a1, const HermiteAxis& b0,
                 const HermiteAxis& b1, double radii, double speed) {
  constexpr int kMaxAdvances = 64;
  constexpr double kTouchSlack = 0.01;
  double s = 0.0;
  for (int it = 0;; ++it) {
    const HermiteAxis a = s == 1.0 ? a1 : a0.blend(a1, s);
    const HermiteAxis b = s == 1.0 ? b1 : b0.blend(b1, s);
    Touch t;
    const double d = closestAxisPoints(a, b, &t.xi_a, &t.xi_b);
    if (d <= radii * (1.0 + kTouchSlack) || it + 1 == kMaxAdvances) {
      const AxisPoint pa = a.at(t.xi_a), pb = b.at(t.xi_b);
      t.normal = d > 1e-6 * radii ? Vec3((pa.position - pb.position) / d)
                                  : pairNormal(pa.position, pa.first.normalized(), pb.position,
                                               pb.first.normalized());
      t.touched = true;
      t.s = s;
      return t;
    }
    if (s == 1.0 || !(speed > 0.0)) return Touch{};
    s = std::min(1.0, s + (d - radii) / speed);
  }
}

}  // namespace pairs
}  // namespace evsim
