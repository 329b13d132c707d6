// Pairs of devices in contact (the effect 'device_contact'; internal to the
// contact solver, contact_solver.cpp): sample points closer than the sum of
// their radii, or (contact.element_pairs) elements whose axes come closer
// than that, found from their boxes and made contacts at the closest points
// of the two axes. The searches: device_pairs.cpp; the axes' distances and
// first touch: axis_distance.cpp.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <memory>
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

/// Candidate point pairs kept from pass to pass (a Verlet list, as
/// PairCandidates for elements): the pairs that came within reach plus
/// twice a skin where it was built; reused while every point of the pass
/// was there, with the same radius, and moved less than the skin since
/// (device_pairs.cpp).
struct PointCandidates {
  double skin{0.0};                       // [m]
  double reach{-1.0};                     // the margin it was built for [m] (< 0: none)
  std::vector<std::vector<int>> slot;     // per device and sample: its index below, or -1
  std::vector<Vec3> at;                   // per point when built [m]
  std::vector<double> r;                  // and its radius [m]
  std::vector<std::array<int, 2>> pairs;  // the candidates (indices above)
  int builds{0}, reuses{0};
};

/// Pairs of points, at least one of them free, closer than the sum of their
/// radii plus `margin` [m] (contact.element_pairs false); see
/// device_pairs.cpp.
std::vector<PointPair> findPointPairs(const std::vector<DeviceModel>& devices,
                                      const std::vector<PointRef>& pts, double margin,
                                      PointCandidates* candidates = nullptr);

/// An element in a configuration (held ones are kinematic obstacles).
struct ElementRef {
  bool free;  // its distal node is free
  int device, element;
  int body;                 // 1: the part of its device cut off by a detachment (a coil), else 0
  int in_lumen_of;          // effect 'coaxial': the outer device whose lumen holds it (-1: none)
  int sample;               // its first sample point (the contact's bookkeeping)
  SamplePoint point;        // that sample: the element's radius and friction
  Eigen::AlignedBox3d box;  // holds its axis grown by its radius, at x and at the step's start [m]
  HermiteAxis axis{};       // its axis at x
  double bow{0.0};          // [m] how far its axis may stray from its chord (HermiteAxis::bow)
  // How its axis moved from the step's start [m]: no point by more than
  // sweep; each by its proximal node's shift, give or take spread.
  double sweep{0.0};
  Vec3 shift{Vec3::Zero()};
  double spread{0.0};
};

/// Two elements whose axes come closer than the sum of their radii plus
/// the margin: the closest points of the two axes. Or two that crossed in
/// the step (swept): the points where they first touched, and the normal
/// there.
struct Pair {
  int a, b;                // indices into the element list
  SamplePoint on_a, on_b;  // the closest points of the axes (element, xi; radius, friction)
  Vec3 pa, pb;             // their positions [m]
  double distance;         // |pa - pb| [m]; swept: (pa - pb) . normal (negative: crossed)
  bool swept{false};
  Vec3 normal{Vec3::Zero()};  // swept: from b toward a where they first touched
};

/// Normal of a contact between two device points, from b to a (unit axis
/// tangents ta, tb; each point standing for its axis's straight stretch of
/// reach_a, reach_b [m] either side); see device_pairs.cpp.
Vec3 pairNormal(const Vec3& pa, const Vec3& ta, const Vec3& pb, const Vec3& tb,
                double reach_a = 0.0, double reach_b = 0.0);

/// The box of an element's axis: its nodes' box grown by its bow (HermiteAxis::bow) [m].
Eigen::AlignedBox3d axisBox(const DeviceModel& model, const DeviceState& x, int element);

/// The closest points (xi_a, xi_b) of two elements' axes: the chords'
/// closest points, refined on the axes; returns their distance [m].
double closestAxisPoints(const HermiteAxis& a, const HermiteAxis& b, double* xi_a, double* xi_b);
double closestAxisPoints(const DeviceModel& ma, const DeviceState& xa, int ea,
                         const DeviceModel& mb, const DeviceState& xb, int eb, double* xi_a,
                         double* xi_b);

/// A lower bound [m] of the distance between two element axes (bows
/// bow_a, bow_b: HermiteAxis::bow): the chords' distance less both bows,
/// or, where tighter, their separation along the direction n joining the
/// chords' closest points. Each axis is a cubic Bezier curve, inside the
/// convex hull of its control points p0, p0 + m0 / 3, p1 - m1 / 3, p1, so
/// along n a's points lie beyond the least of its control points' and b's
/// below the greatest of its own (a separating axis). A coil's turns lying
/// side by side bow across n, not along it: there the separation is within
/// micrometres of the axes' distance where the bows are tens of
/// micrometres, and findPairs spares closestAxisPoints for most of them.
double axisGapBound(const HermiteAxis& a, double bow_a, const HermiteAxis& b, double bow_b);

/// Where two moving axes first come within `radii` [m] of each other: on
/// the path that moves each axis point straight from its place on a0 (b0)
/// to its place on a1 (b1), s from 0 to 1.
struct Touch {
  bool touched{false};
  double s{0.0};                // the path parameter
  double xi_a{0.0}, xi_b{0.0};  // the closest points there
  Vec3 normal{Vec3::Zero()};    // from b toward a there
};
/// Conservative advancement (see axis_distance.cpp); `speed` [m] bounds how
/// far any point of axis a moves relative to any point of axis b over the
/// whole path (from ElementRef::sweep, shift and spread of both).
Touch firstTouch(const HermiteAxis& a0, const HermiteAxis& a1, const HermiteAxis& b0,
                 const HermiteAxis& b1, double radii, double speed);

/// The elements' axes in a configuration (the step's start, for the swept
/// test), each computed when first asked for and kept (for the step).
class StartAxes {
 public:
  StartAxes(const std::vector<DeviceModel>& devices, const std::vector<DeviceState>& x);
  /// Element e of device d.
  const HermiteAxis& axis(int d, int e) const;
  /// Its bow [m] (HermiteAxis::bow).
  double bow(int d, int e) const;

 private:
  const std::vector<DeviceModel>* devices_;
  const std::vector<DeviceState>* x_;
  // (left uninitialised until asked for: a long coil has thousands)
  std::vector<std::unique_ptr<HermiteAxis[]>> axis_;
  mutable std::vector<std::vector<double>> bow_;  // -1: not yet computed
};

/// Candidate element pairs kept from pass to pass (a Verlet list): the
/// pairs whose boxes, grown by a skin, came within reach of each other where
/// it was built (the pairs of two held elements left out); reused while
/// every element is free or held, and on its body, as it was there and its
/// box stays within its box there grown by the skin (device_pairs.cpp).
///
/// Each candidate also keeps a lower bound of its axes' distance as of the
/// last pass (`slack`): measured where that pass checked it, else the
/// bound before less how far both axes moved since. An axis is a cubic
/// Bezier curve, so each of its points moved by a Bezier combination of
/// its control points' displacements, and the distance now is at least
/// the last bound less how far the two axes moved relative to each other
/// since the last pass (bounded from those displacements: Motion). A pass
/// skips the candidates that bound keeps apart (findPairs). A build
/// carries the slack of the list it replaces over to the pairs in both, by
/// the same rule from where their axes were when it was last measured.
struct PairCandidates {
  double skin{0.0};                          // [m]
  double reach{-1.0};                        // the reach it was built for [m] (< 0: none)
  std::vector<std::vector<int>> slot;        // per device and element: its index below, or -1
  std::vector<Eigen::AlignedBox3d> box;      // per element when built: its box grown by the skin
  std::vector<char> free;                    // and whether it was free
  std::vector<int> body;                     // and its body (ElementRef::body)
  std::vector<std::array<Vec3, 4>> control;  // its axis' Bezier control points at the last pass [m]
  std::vector<std::array<int, 2>> pairs;     // the candidates (indices above)
  std::vector<double> slack;                 // per candidate [m] (-inf: not yet measured)
  struct Motion {   // how an axis moved between two passes [m] (device_pairs.cpp)
    Vec3 shift;     // its control points' mean displacement
    double spread;  // the farthest of them from that
    double drift;   // the farthest of them
  };
  struct Reaches {                      // per element, a pass's scratch, one array per quantity:
    std::vector<double> x, y, z;        // its motion since the last pass: Motion::shift [m]
    std::vector<double> spread, drift;  // and Motion's others [m]
    std::vector<double> radius, sweep;  // its radius, and ElementRef::sweep [m]
    void resize(size_t n) {
      for (auto* v : {&x, &y, &z, &spread, &drift, &radius, &sweep}) v->resize(n);
    }
  };
  Reaches reaches;
  std::vector<int> unsure;  // a pass's scratch: the candidates it checks
  int builds{0}, reuses{0};
  long kept_apart{0};  // candidates a pass skipped on their slack
  long carried{0};     // of those, at a build, on the slack of the list it replaced
};

/// Pairs of elements, at least one of them free, whose axes at x come
/// closer than the sum of their radii plus `margin` [m]
/// (contact.element_pairs true), and, given the step's start `from`, the
/// pairs that crossed between from and x: those that overlap at x, and
/// with `apart_too` those apart there too (they passed through); see
/// device_pairs.cpp.
std::vector<Pair> findPairs(const std::vector<DeviceModel>& devices,
                            const std::vector<DeviceState>& x,
                            const std::vector<ElementRef>& elements, double margin,
                            const StartAxes* from = nullptr, bool apart_too = true,
                            PairCandidates* candidates = nullptr);

}  // namespace pairs
}  // namespace evsim
