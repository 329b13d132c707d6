// Pairs of devices in contact (the effect 'device_contact'; internal to the
// contact solver, contact_solver.cpp): sample points closer than the sum of
// their radii, or (contact.element_pairs) elements whose axes come closer
// than that, found from their boxes and made contacts at the closest points
// of the two axes.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {
namespace pairs {

/// A sample point in a configuration (held ones are kinematic obstacles).
struct PointRef {
  bool free;
  int device, sample, element;
  double s;         // material coordinate [m]
  Vec3 p;           // [m]
  double r;         // [m]
  int in_lumen_of;  // effect 'coaxial': the outer device whose lumen holds it (-1: none)
  int body{0};      // 1: the part of its device cut off by a detachment (a coil), else 0
};

struct PointPair {
  int a, b;  // indices into the point list
  double distance;
};

/// Pairs of points, at least one of them free, closer than the sum of their
/// radii plus `margin` [m] (contact.element_pairs false); see
/// device_pairs.cpp.
std::vector<PointPair> findPointPairs(const std::vector<DeviceModel>& devices,
                                      const std::vector<PointRef>& pts, double margin);

/// An element in a configuration (held ones are kinematic obstacles).
struct ElementRef {
  bool free;  // its distal node is free
  int device, element;
  int body;                 // 1: the part of its device cut off by a detachment (a coil), else 0
  int in_lumen_of;          // effect 'coaxial': the outer device whose lumen holds it (-1: none)
  int sample;               // its first sample point (the contact's bookkeeping)
  SamplePoint point;        // that sample: the element's radius and friction
  Eigen::AlignedBox3d box;  // holds its axis grown by its radius [m]
  double bow{0.0};          // [m] how far its axis may stray from its chord (axisBow)
};

/// Two elements whose axes come closer than the sum of their radii plus
/// the margin: the closest points of the two axes.
struct Pair {
  int a, b;                // indices into the element list
  SamplePoint on_a, on_b;  // the closest points of the axes (element, xi; radius, friction)
  Vec3 pa, pb;             // their positions [m]
  double distance;         // |pa - pb| [m]
};

/// Normal of a contact between two device points, from b to a (axis
/// tangents ta, tb); see device_pairs.cpp.
Vec3 pairNormal(const Vec3& pa, const Vec3& ta, const Vec3& pb, const Vec3& tb);

/// A bound [m] of how far an element's axis (cubic Hermite,
/// contact_point.h) of length L [m] strays from its chord p1 - p0, its
/// nodes' unit tangents t0, t1.
double axisBow(double L, const Vec3& p0, const Vec3& p1, const Vec3& t0, const Vec3& t1);
/// The same for an element of a device in a configuration.
double axisBow(const DeviceModel& model, const DeviceState& x, int element);

/// The box of an element's axis: its nodes' box grown by axisBow [m].
Eigen::AlignedBox3d axisBox(const DeviceModel& model, const DeviceState& x, int element);

/// The closest points (xi_a, xi_b) of two elements' axes: the chords'
/// closest points, refined on the axes; returns their distance [m].
double closestAxisPoints(const DeviceModel& ma, const DeviceState& xa, int ea,
                         const DeviceModel& mb, const DeviceState& xb, int eb, double* xi_a,
                         double* xi_b);

/// Pairs of elements, at least one of them free, whose axes at x come
/// closer than the sum of their radii plus `margin` [m]
/// (contact.element_pairs true); see device_pairs.cpp.
std::vector<Pair> findPairs(const std::vector<DeviceModel>& devices,
                            const std::vector<DeviceState>& x,
                            const std::vector<ElementRef>& elements, double margin);

}  // namespace pairs
}  // namespace evsim
