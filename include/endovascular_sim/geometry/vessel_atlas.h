// The named vessels of a centreline tree: which vessel a point lies in, how
// deep along it, and the path of vessels between two of them. What a
// clinician reads off the screen; navigation targets and the autopilot use
// it, contacts never do.
//
// A vessel is the chain of centreline points that share a name
// (Centerline::vessel). Its origin is the point of its parent vessel where
// it branches off (the junction on the parent's centreline); its depth
// coordinate s [m] is the path length along its centreline from there.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/centerline.h"

namespace evsim {

struct NamedVessel {
  std::string name;
  int parent{-1};     // vessel it branches off (-1 for a root)
  int generation{0};  // branchings from its root vessel
  int origin{-1};     // centreline point it starts from (the junction; its first point for a root)
  double origin_depth{0.0};  // [m] depth of the origin along the parent vessel
  double length{0.0};        // [m] along its centreline, from the origin
  double radius{0.0};        // smallest lumen radius along it [m]
  std::vector<int> children;
};

/// Where a point lies among the named vessels.
struct VesselLocation {
  int vessel{-1};                // -1: no vessels
  double depth{0.0};             // [m] along the vessel's centreline from its origin
  double radial{0.0};            // distance from the centreline / lumen radius there [-]
  bool inside{false};            // radial <= 1: within the lumen (of the centreline's radii)
  Vec3 direction{Vec3::Zero()};  // unit tangent of the centreline there, away from the origin
};

class VesselAtlas {
 public:
  VesselAtlas() = default;
  explicit VesselAtlas(const Centerline& centerline);

  const std::vector<NamedVessel>& vessels() const { return vessels_; }
  /// Index of a vessel by name, -1 when unknown.
  int find(const std::string& name) const;
  /// Up to `count` names nearest to `name` (edit distance), for messages.
  std::vector<std::string> closestNames(const std::string& name, int count = 3) const;

  /// The vessel a point [m] lies in: of the vessels whose lumen holds it,
  /// the deepest (most branchings from the root) — except that a branch's
  /// stretch still within its parent's lumen (its ostium) counts as the
  /// parent. A point in no lumen gets the nearest vessel (radial > 1).
  VesselLocation locate(const Vec3& p) const;

  /// Where a point lies relative to one given vessel (its nearest point on
  /// that vessel's centreline), whether or not another vessel holds it.
  VesselLocation locateIn(int vessel, const Vec3& p) const;

  /// Vessels from `from` to `to` through the tree: up to their common
  /// ancestor, then down; empty when they are not connected.
  std::vector<int> path(int from, int to) const;

  /// Path length [m] from `depth` along the first vessel of `path` to
  /// `target_depth` inside its last: along each vessel to the next junction.
  double pathLength(const std::vector<int>& path, double depth, double target_depth) const;

  /// Position [m] and unit direction (away from the origin) on a vessel's
  /// centreline at depth s [m] (clamped to [0, length]).
  Vec3 pointAt(int vessel, double s, Vec3* direction = nullptr) const;

 private:
  struct Segment {
    int a, b;  // centreline points, a the parent
    int vessel;
    double s0, s1;  // depth of a and b along the vessel [m]
  };
  /// Segments whose box (grown by their radius) meets p's grid cell.
  const std::vector<int>& segmentsNear(const Vec3& p) const;
  long cellKey(const Vec3& p) const;

  std::vector<Vec3> position_;
  std::vector<double> radius_;
  std::vector<NamedVessel> vessels_;
  std::vector<Segment> segments_;
  std::vector<std::vector<int>> vessel_segments_;  // per vessel, from the origin outward
  std::unordered_map<std::string, int> by_name_;
  double cell_{0.01};  // [m]
  std::unordered_map<long, std::vector<int>> grid_;
};

}  // namespace evsim
