// Points of a device where contacts are detected, sampled along its elements
// (not only at nodes) with the beam's cubic Hermite interpolation. Declared
// and documented in endovascular_sim/contact/contact_point.h.
#include "endovascular_sim/contact/contact_point.h"

#include <algorithm>
#include <cmath>

namespace evsim {
namespace {

struct Hermite {
  double h00, h10, h01, h11;
  explicit Hermite(double t) {
    const double t2 = t * t, t3 = t2 * t;
    h00 = 2 * t3 - 3 * t2 + 1;
    h10 = t3 - 2 * t2 + t;
    h01 = -2 * t3 + 3 * t2;
    h11 = t3 - t2;
  }
};

/// d/dt and d2/dt2 of the Hermite basis.
struct HermiteDerivatives {
  double d00, d10, d01, d11, s00, s10, s01, s11;
  explicit HermiteDerivatives(double t) {
    d00 = 6 * t * t - 6 * t;
    d10 = 3 * t * t - 4 * t + 1;
    d01 = -d00;
    d11 = 3 * t * t - 2 * t;
    s00 = 12 * t - 6;
    s10 = 6 * t - 4;
    s01 = -s00;
    s11 = 6 * t - 2;
  }
};

Vec3 tangent(const DeviceState& s, int node) { return s.rotation[node] * Vec3::UnitX(); }

}  // namespace

std::vector<SamplePoint> sampleDevice(const DeviceModel& model, double spacing) {
  std::vector<SamplePoint> points;
  const int ne = model.num_nodes - 1;
  for (int e = 0; e < ne; ++e) {
    const int k =
        std::max(1, static_cast<int>(std::ceil(model.elements[e].length / spacing - 1e-9)));
    const double r = std::max(model.node_radius[e], model.node_radius[e + 1]);
    const double mu = model.section_friction[model.element_section[e]];
    for (int j = 0; j < k; ++j) points.push_back({e, static_cast<double>(j) / k, r, mu});
  }
  points.push_back(
      {ne - 1, 1.0, model.node_radius[ne], model.section_friction[model.element_section[ne - 1]]});
  return points;
}

Vec3 samplePosition(const DeviceModel& model, const DeviceState& state, const SamplePoint& s) {
  Vec3 p;
  samplePositions(model, state, &s, 1, &p);
  return p;
}

void samplePositions(const DeviceModel& model, const DeviceState& state, const SamplePoint* s,
                     int count, Vec3* out) {
  if (count == 0) return;
  const int a = s[0].element, b = a + 1;
  const double L = model.elements[a].length;
  Vec3 ta = Vec3::Zero(), tb = Vec3::Zero();
  bool tangents = false;  // formed on the first interior point
  for (int j = 0; j < count; ++j) {
    if (s[j].xi == 0.0) {
      out[j] = state.position[a];
      continue;
    }
    if (s[j].xi == 1.0) {
      out[j] = state.position[b];
      continue;
    }
    if (!tangents) {
      ta = tangent(state, a);
      tb = tangent(state, b);
      tangents = true;
    }
    const Hermite h(s[j].xi);
    out[j] =
        h.h00 * state.position[a] + h.h10 * L * ta + h.h01 * state.position[b] + h.h11 * L * tb;
  }
}

AxisPoint axisPoint(const DeviceModel& model, const DeviceState& state, int element, double xi) {
  return HermiteAxis::of(model, state, element).at(xi);
}

HermiteAxis HermiteAxis::of(const DeviceModel& model, const DeviceState& state, int element) {
  const double L = model.elements[element].length;
  return {state.position[element], state.position[element + 1], L * tangent(state, element),
          L * tangent(state, element + 1)};
}

HermiteAxis HermiteAxis::blend(const HermiteAxis& to, double s) const {
  return {p0 + s * (to.p0 - p0), p1 + s * (to.p1 - p1), m0 + s * (to.m0 - m0),
          m1 + s * (to.m1 - m1)};
}

AxisPoint HermiteAxis::at(double xi) const {
  const Hermite h(xi);
  const HermiteDerivatives d(xi);
  AxisPoint out;
  out.position = h.h00 * p0 + h.h10 * m0 + h.h01 * p1 + h.h11 * m1;
  out.first = d.d00 * p0 + d.d10 * m0 + d.d01 * p1 + d.d11 * m1;
  out.second = d.s00 * p0 + d.s10 * m0 + d.s01 * p1 + d.s11 * m1;
  return out;
}

double HermiteAxis::bow() const {
  // p(xi) - chord(xi) = h10 (m0 - d) + h11 (m1 - d), d = p1 - p0 (as
  // h01 - xi = -(h10 + h11)): |h10|, |h11| <= 4 / 27 on [0, 1].
  const Vec3 d = p1 - p0;
  return 4.0 / 27.0 * ((m0 - d).norm() + (m1 - d).norm());
}

double HermiteAxis::closestParameter(const Vec3& y, double xi) const {
  return AxisCubic(*this).closestParameter(y, xi);
}

double AxisCubic::closestParameter(const Vec3& y, double xi) const {
  for (int it = 0; it < 8; ++it) {
    const AxisPoint a = at(xi);
    const Vec3 r = a.position - y;
    const double g = a.first.dot(r);
    const double h = a.second.dot(r) + a.first.squaredNorm();
    if (!(h > 0.0)) break;
    const double next = std::clamp(xi - g / h, 0.0, 1.0);
    const bool done = std::abs(next - xi) < 1e-10;  // (the next error about its square)
    xi = next;
    if (done) break;
  }
  return xi;
}

Row12 contactRow(const DeviceModel& model, const DeviceState& state, const SamplePoint& s,
                 const Vec3& n) {
  const Hermite h(s.xi);
  const double L = model.elements[s.element].length;
  Row12 row;
  row.segment<3>(0) = h.h00 * n.transpose();
  row.segment<3>(3) = h.h10 * L * tangent(state, s.element).cross(n).transpose();
  row.segment<3>(6) = h.h01 * n.transpose();
  row.segment<3>(9) = h.h11 * L * tangent(state, s.element + 1).cross(n).transpose();
  return row;
}

}  // namespace evsim
