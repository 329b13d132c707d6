// Iodinated contrast in the vessels: an injection fills the vessel tree
// downstream of a point (the catheter's tip) for a while, then washes out.
// Blood flows from the centreline's roots to its leaves, so downstream is
// the subtree below the segment holding the point.
#pragma once

#include <memory>
#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/centerline.h"

namespace evsim {

struct Injection {
  std::vector<char> filled;   // per centreline point: its segment (to its parent) fills
  double start{0.0};          // [s]
  double duration{1.0};       // [s] at full concentration
  double concentration{0.0};  // iodine in the filled blood [kg/m^3]
  double washout{1.0};        // [s] of the linear clearance after it
};

class ContrastAgent {
 public:
  ContrastAgent() = default;
  explicit ContrastAgent(std::shared_ptr<const Centerline> centerline);

  /// Fills the segment nearest to `at` [m] and every segment below it from
  /// `start` [s] for `duration` [s] with `concentration` [kg/m^3], then
  /// clears them over `washout` [s]. Returns the segments filled (0
  /// without vessels).
  int inject(const Vec3& at, double start, double duration, double concentration, double washout);
  /// Iodine concentration [kg/m^3] at time t [s] in the segment that ends
  /// at centreline point k (the strongest of the injections).
  double concentration(int point, double t) const;
  /// Whether any segment holds contrast at t.
  bool active(double t) const;
  /// The centreline point whose segment (to its parent) lies nearest to p.
  int nearestSegment(const Vec3& p) const;
  /// The point's segment and every segment below it (downstream).
  std::vector<int> downstream(int point) const;
  void clear() { injections_.clear(); }

 private:
  static double level(const Injection& j, double t);
  std::shared_ptr<const Centerline> centerline_;
  std::vector<std::vector<int>> children_;
  std::vector<Injection> injections_;
};

}  // namespace evsim
