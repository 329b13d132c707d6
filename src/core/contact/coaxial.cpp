// Coaxial devices: an inner device (a guidewire in a catheter, a coil in a
// microcatheter) enters through its outer device's introducer and must stay
// inside the outer device's lumen where the two overlap. Declared and
// documented in endovascular_sim/contact/coaxial.h.
#include "endovascular_sim/contact/coaxial.h"

#include <algorithm>
#include <cmath>

namespace evsim {
namespace {

/// Element holding material coordinate s and the parameter there.
void elementAt(const DeviceModel& model, double s, int* element, double* xi) {
  const int ne = model.num_nodes - 1;
  const auto it = std::upper_bound(model.node_s.begin(), model.node_s.end(), s);
  *element = std::clamp(static_cast<int>(it - model.node_s.begin()) - 1, 0, ne - 1);
  *xi = std::clamp((s - model.node_s[*element]) / model.elements[*element].length, 0.0, 1.0);
}

/// Parameter of y's projection on element e's chord, in [0, 1]: where the
/// search for the closest axis point starts.
double chordParameter(const DeviceState& x, int e, const Vec3& y) {
  const Vec3 chord = x.position[e + 1] - x.position[e];
  return std::clamp(chord.dot(y - x.position[e]) / chord.squaredNorm(), 0.0, 1.0);
}

/// The outer element at the inner point's path length (the same path
/// length on both devices: a guess, the inner device runs off the axis in
/// bends). Returns -1 outside the overlap: no lumen holds the point.
int guessedOuterElement(const DeviceModel& inner, const DeviceState& x_inner, const SamplePoint& s,
                        const DeviceModel& outer, const DeviceState& x_outer) {
  const double a = pathLength(inner, x_inner, materialCoordinate(inner, s));
  if (a <= 0.0 || a >= x_outer.inserted_length) return -1;
  int e;
  double xi;
  elementAt(outer, a + outer.length - x_outer.inserted_length, &e, &xi);
  return e;
}

/// Closest point of one element's axis to y: Newton (closestParameter)
/// from the chord's projection. Returns its parameter; *at the axis point
/// there, *distance its distance to y [m].
double closestOnElement(const DeviceModel& model, const DeviceState& x, int e, const Vec3& y,
                        double* distance, AxisPoint* at) {
  const HermiteAxis axis = HermiteAxis::of(model, x, e);  // (its tangents: once)
  const double xi = axis.closestParameter(y, chordParameter(x, e, y));
  *at = axis.at(xi);
  *distance = (at->position - y).norm();
  return xi;
}

/// The outer device's frame at (element, xi): nodal frames interpolated.
Quat frameAt(const DeviceState& x, int element, double xi) {
  return x.rotation[element].slerp(xi, x.rotation[element + 1]);
}

Mat3 rotationX(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix(); }

}  // namespace

double pathLength(const DeviceModel& model, const DeviceState& state, double s) {
  return s - (model.length - state.inserted_length);
}

double materialCoordinate(const DeviceModel& model, const SamplePoint& s) {
  return model.node_s[s.element] + s.xi * model.elements[s.element].length;
}

LumenLocation locateInLumen(const DeviceModel& inner, const DeviceState& x_inner,
                            const SamplePoint& s, const DeviceModel& outer,
                            const DeviceState& x_outer) {
  LumenLocation loc;
  const int e0 = guessedOuterElement(inner, x_inner, s, outer, x_outer);
  if (e0 < 0) return loc;
  loc.inside = true;
  // The closest point within two elements of the guess.
  const Vec3 p = samplePosition(inner, x_inner, s);
  const int ne = outer.num_nodes - 1;
  // The guessed element first; another is searched only if it can be
  // closer. A point of element e's axis lies within its arc length l of
  // both nodes, so it is at least (|p - x_e| + |p - x_e+1| - l) / 2 from p
  // (l bounded by 1.1 rest lengths). The choice is the same as searching
  // all five (ties to the lowest e).
  double d0;
  AxisPoint c0;  // the guessed element's closest axis point
  const double xi0_closest = closestOnElement(outer, x_outer, e0, p, &d0, &c0);
  AxisPoint c = c0;  // the closest of all
  double best = INFINITY;
  for (int e = std::max(0, e0 - 2); e <= std::min(ne - 1, e0 + 2); ++e) {
    double d = d0, xi = xi0_closest;
    AxisPoint at = c0;
    if (e != e0) {
      const double bound =
          0.5 * ((p - x_outer.position[e]).norm() + (p - x_outer.position[e + 1]).norm() -
                 1.1 * outer.elements[e].length);
      if (bound > std::min(best, d0)) continue;
      xi = closestOnElement(outer, x_outer, e, p, &d, &at);
    }
    if (d < best) {
      best = d;
      loc.axis.element = e;
      loc.axis.xi = xi;
      c = at;
    }
  }
  const int section = outer.element_section[loc.axis.element];
  loc.axis.radius = outer.section_lumen_radius[section];
  loc.axis.friction = outer.section_lumen_friction[section];
  loc.center = c.position;
  loc.tangent = c.first.normalized();
  const Vec3 d = p - loc.center;
  loc.across = d - d.dot(loc.tangent) * loc.tangent;
  loc.clearance = loc.axis.radius - s.radius;
  const double across = loc.across.norm();
  loc.normal = across > 0.0 ? Vec3(-loc.across / across) : loc.tangent.unitOrthogonal();
  return loc;
}

bool surelyWithinLumen(const DeviceModel& inner, const DeviceState& x_inner, const SamplePoint& s,
                       const DeviceModel& outer, const DeviceState& x_outer, double allowance,
                       OuterAxisCache* cache, const Vec3* position) {
  const int e = guessedOuterElement(inner, x_inner, s, outer, x_outer);
  if (e < 0) return true;  // no lumen holds it
  if (cache->element != e) {
    cache->element = e;
    cache->axis = HermiteAxis::of(outer, x_outer, e);
    // The closest point may lie on the two elements either side (another
    // section): the narrowest of their lumens.
    cache->lumen_radius = INFINITY;
    for (int f = std::max(0, e - 2); f <= std::min(outer.num_nodes - 2, e + 2); ++f)
      cache->lumen_radius =
          std::min(cache->lumen_radius, outer.section_lumen_radius[outer.element_section[f]]);
  }
  // The point of element e's axis where closestOnElement's search starts:
  // the closest point of the elements searched is no farther, and |across|
  // there is no longer than its distance.
  const Vec3 p = position ? *position : samplePosition(inner, x_inner, s);
  const double reach = cache->lumen_radius - s.radius + allowance;
  const Vec3 start = cache->axis.at(chordParameter(x_outer, e, p)).position;
  return reach > 0.0 && (p - start).squaredNorm() <= reach * reach;
}

DeviceState placeInside(const DeviceModel& inner, const Introducer& intro, double inserted_length,
                        double rotation_angle, const DeviceModel& outer,
                        const DeviceState& x_outer) {
  DeviceState s = placeDevice(inner, intro, inserted_length, rotation_angle);
  int last = -1;  // last node on the outer axis
  for (int i = lastHeldNode(inner, inserted_length) + 1; i < inner.num_nodes; ++i) {
    const double a = pathLength(inner, s, inner.node_s[i]);
    if (a > x_outer.inserted_length + 1e-12) break;
    int e;
    double xi;
    const double s_out = a + outer.length - x_outer.inserted_length;
    elementAt(outer, s_out, &e, &xi);
    s.position[i] = axisPoint(outer, x_outer, e, xi).position;
    // Twist continues from the sheath: the inner device's own rotation and
    // rest twist relative to the outer device's.
    const double twist_out =
        outer.rest_twist[e] + xi * (outer.rest_twist[e + 1] - outer.rest_twist[e]);
    s.rotation[i] =
        Quat(frameAt(x_outer, e, xi).toRotationMatrix() *
             rotationX(rotation_angle - x_outer.rotation_angle + inner.rest_twist[i] - twist_out));
    last = i;
  }
  if (last < 0) return s;
  const Mat3 T = s.rotation[last].toRotationMatrix() * inner.rest_rotation[last].transpose();
  for (int i = last + 1; i < inner.num_nodes; ++i) {
    s.position[i] = s.position[last] + T * (inner.rest_position[i] - inner.rest_position[last]);
    s.rotation[i] = Quat(T * inner.rest_rotation[i]);
  }
  return s;
}

}  // namespace evsim
