// Points of a device where contacts are detected, sampled along its elements
// (not only at nodes) with the beam's cubic Hermite interpolation:
//   p(xi) = h00 x1 + h10 L t1 + h01 x2 + h11 L t2,   xi in [0, 1],
// t_i = R_i e_x the nodal tangents, L the element's rest length. A contact
// with unit normal n constrains n . (p - i0) >= 0; its row of H over the two
// nodes' 12 DOFs (dx1, dtheta1, dx2, dtheta2) is
//   [h00 n^T, h10 L (t1 x n)^T, h01 n^T, h11 L (t2 x n)^T].
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {

using Row12 = Eigen::Matrix<double, 1, 12>;

struct SamplePoint {
  int element{0};        // between nodes element and element + 1
  double xi{0.0};        // [0, 1] along the element
  double radius{0.0};    // device radius there [m]
  double friction{0.0};  // Coulomb coefficient of its section [-]
};

/// Sample points of one device: every node, and interior points so that
/// neighbours are at most `spacing` [m] apart along each element.
std::vector<SamplePoint> sampleDevice(const DeviceModel& model, double spacing);

/// Position of a sample point in a configuration [m].
Vec3 samplePosition(const DeviceModel& model, const DeviceState& state, const SamplePoint& s);
/// samplePosition of `count` consecutive sample points s[0..count) of one
/// element into out[0..count), the element's two tangents formed once (the
/// same numbers).
void samplePositions(const DeviceModel& model, const DeviceState& state, const SamplePoint* s,
                     int count, Vec3* out);

/// A point of the device axis (cubic Hermite) and its derivatives in xi.
struct AxisPoint {
  Vec3 position;  // p(xi) [m]
  Vec3 first;     // dp/dxi [m]
  Vec3 second;    // d2p/dxi2 [m]
};
AxisPoint axisPoint(const DeviceModel& model, const DeviceState& state, int element, double xi);

/// An element's axis as the cubic Hermite curve of its data: end points p0,
/// p1 [m] and end tangents times the element's length m0 = L t0, m1 = L t1
/// [m]. The curve is linear in its data: the blend of two configurations'
/// axes moves each axis point on the straight line between its two places.
struct HermiteAxis {
  Vec3 p0, p1, m0, m1;

  /// Element e's axis in a configuration.
  static HermiteAxis of(const DeviceModel& model, const DeviceState& state, int element);
  /// (1 - s) this + s to: every axis point s of the way to its place on `to`.
  HermiteAxis blend(const HermiteAxis& to, double s) const;
  AxisPoint at(double xi) const;
  /// A bound [m] of how far the curve strays from its chord p1 - p0.
  double bow() const;
  /// The parameter in [0, 1] of the curve's point closest to y: Newton on
  /// |p(xi) - y|^2 / 2 from xi (at most 8 steps, until a step is below 1e-10).
  double closestParameter(const Vec3& y, double xi) const;
};

/// The same curve in the power basis, p(xi) = c0 + c1 xi + c2 xi^2 + c3 xi^3
/// [m]: a point and its derivatives in 18 multiply-adds (Horner) instead of
/// the Hermite basis' 36 and its 12 weights, for Newton's many evaluations
/// (closest points of two axes: on a packed coil a million a hundred
/// steps). Equal to HermiteAxis::at to round-off.
struct AxisCubic {
  Vec3 c0, c1, c2, c3;
  explicit AxisCubic(const HermiteAxis& a)
      : c0(a.p0),
        c1(a.m0),
        c2(3.0 * (a.p1 - a.p0) - 2.0 * a.m0 - a.m1),
        c3(2.0 * (a.p0 - a.p1) + a.m0 + a.m1) {}
  Vec3 position(double xi) const { return c0 + xi * (c1 + xi * (c2 + xi * c3)); }
  AxisPoint at(double xi) const {
    return {position(xi), c1 + xi * (2.0 * c2 + 3.0 * xi * c3), 2.0 * c2 + 6.0 * xi * c3};
  }
  /// As HermiteAxis::closestParameter.
  double closestParameter(const Vec3& y, double xi) const;
};

/// Row of H for a contact of normal n at a sample point.
Row12 contactRow(const DeviceModel& model, const DeviceState& state, const SamplePoint& s,
                 const Vec3& n);

}  // namespace evsim
