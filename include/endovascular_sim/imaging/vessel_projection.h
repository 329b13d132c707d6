// The lumen as X-rays cross it: for every ray of a camera, the path length
// through the vessels' implicit surface (g >= 0, the paper's convolution
// surface at the wall), split by the centreline segment it belongs to, so
// that contrast in some vessels and not others attenuates the right rays.
//
// Each ray is first cut to the bounding capsules of the segments it passes
// (radius kCapsuleScale times the vessel's, which holds the blended surface),
// then the field is sampled along it every half of the smallest radius
// among them and each sign change is refined to kRootTolerance: the path
// lengths are exact to that tolerance, except for a chord shorter than the
// sampling step (a ray grazing the wall), which can be missed.
#pragma once

#include <map>
#include <vector>

#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "endovascular_sim/imaging/c_arm.h"

namespace evsim {

class VesselProjection {
 public:
  static constexpr double kCapsuleScale = 1.6;
  static constexpr double kRootTolerance = 1e-7;  // [m]

  struct Piece {
    int segment;   // centreline point whose segment (to its parent) holds it
    float length;  // [m], averaged over the pixel's rays
  };

  /// Traces the rays of `camera` (supersampling^2 per pixel) through the
  /// lumen of `field` at `motion`; `margin` [m] grows the capsules (moving
  /// vessels). With `only` (per centreline point, non-zero: its segment is
  /// wanted) the rays are traced through those segments' capsules and the
  /// capsules that touch them (so that a stretch of lumen goes to the same
  /// segment as in the whole trace), not through the rest of the tree: the
  /// pieces of the wanted segments are the whole trace's, at a cost in
  /// proportion to the wanted part (a contrast-filled subtree of moving
  /// vessels, traced each frame).
  void build(const VesselField& field, const Centerline& centerline,
             const std::vector<AneurysmSpec>& aneurysms, const XrayCamera& camera,
             int supersampling, const MotionSnapshot& motion = {}, double margin = 0.0,
             const std::vector<char>* only = nullptr);

  /// Adds, per pixel, sum over its pieces of length * mu(segment), with
  /// mu [1/m] per centreline point.
  void addAttenuation(const std::vector<double>& mu, std::vector<float>* image) const;

  /// The pixel's total path length through the lumen [m].
  double pathLength(int pixel) const;
  long numPieces() const { return static_cast<long>(pieces_.size()); }
  long fieldEvaluations() const { return evaluations_; }
  bool built() const { return !offset_.empty(); }

 private:
  /// The pixels' pieces (segment, chord) into the CSR arrays below.
  void pack(const std::vector<std::map<int, double>>& per_pixel, const std::vector<long>& pixel_of,
            long pixels);

  std::vector<long> offset_;  // CSR over pixels
  std::vector<Piece> pieces_;
  long evaluations_{0};
};

}  // namespace evsim
