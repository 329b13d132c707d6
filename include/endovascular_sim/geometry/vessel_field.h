// The implicit vessel surface: a convolution field of centreline segments
// (and aneurysm spheres), indexed by a uniform grid over their supports.
//
// Inside the lumen g = f - T > 0, outside g < 0, on the wall g = 0; grad f
// points into the lumen. For a device of radius r every primitive's width is
// taken as R = (rho - r) / alpha, so the surface g = 0 is the wall offset
// inward by r (exactly along straight vessels). Vessels narrower than the
// device are closed to it.
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/geometry/implicit_surface.h"
#include "endovascular_sim/geometry/kernel.h"

namespace evsim {

/// A saccular aneurysm's dome: a sphere primitive blended with the vessels.
struct AneurysmSpec {
  Vec3 center{Vec3::Zero()};  // [m]
  double radius{0.0};         // dome radius [m]
};

/// Periodic displacement of the vessels near a centre:
/// u(x, t) = phi(|x - center| / radius) amplitude sin(2 pi frequency t + phase),
/// phi(s) = (1 - s^2)^2 for s < 1, 0 beyond.
struct MotionRegion {
  Vec3 center{Vec3::Zero()};     // [m]
  double radius{0.0};            // [m]
  Vec3 amplitude{Vec3::Zero()};  // [m]
  double frequency{0.0};         // [Hz]
  double phase{0.0};             // [rad]
};

struct VesselFieldOptions {
  double alpha{0.6};  // iso radius / kernel width, in (0, 1): smaller blends more
  /// The most a wall that gives way (MotionSnapshot::wall) moves a
  /// centreline point and widens its radius [m]: the primitives' supports
  /// are grown by it (0: the wall stays at rest).
  double wall_reach{0.0};
};

class VesselField : public ImplicitSurface {
 public:
  VesselField() = default;
  VesselField(const Centerline& centerline, const std::vector<AneurysmSpec>& aneurysms,
              const std::vector<MotionRegion>& motion, const VesselFieldOptions& options);

  /// g = f - T and grad f [1/m] at p for a device of radius r [m].
  FieldSample evaluate(const Vec3& p, double device_radius,
                       const MotionSnapshot& motion = {}) const override;

  /// Upper bound of |Hessian of f| [1/m^2] over the axis-aligned box of the
  /// segment [p0, p1] (motion included).
  double hessianBound(const Vec3& p0, const Vec3& p1, double device_radius) const override;
  /// Tabulates every grid cell's Hessian bound for these device radii [m]
  /// (a scene's), so that hessianBound() for them reads one number per cell
  /// instead of summing the cell's primitives: detection asks for it at
  /// every certified ball, and a cell of the 4,000-vessel network holds
  /// dozens of primitives. The table holds the same sums, rounded up to
  /// float (4 bytes per cell and radius; at most kMaxTabulatedCells cells).
  void tabulateHessianBounds(const std::vector<double>& device_radii);
  static constexpr long kMaxTabulatedCells = 1L << 25;

  MotionSnapshot motionAt(double t) const override;
  /// Displacement u(x) [m] of the motion field at a point (what a vessel
  /// centreline point there is moved by; displays move mesh vertices by it).
  Vec3 displacement(const Vec3& x, const MotionSnapshot& motion) const;
  bool moves() const { return !motion_.empty(); }
  /// Balls that follow the motion (implicit_surface.h). The displacement
  /// change is the motion field's; the deformation rate is the regions'
  /// falloff slope times their displacement changes; the sensitivity sums,
  /// over the primitives listed in the grid cells of the box c +- half_width,
  /// the kernel's bounds (vessel_field.cpp).
  Vec3 displacementChange(const Vec3& x, const std::vector<Vec3>& m0,
                          const std::vector<Vec3>& m1) const override;
  double deformationRate(const std::vector<Vec3>& m0, const std::vector<Vec3>& m1) const override;
  bool motionSensitivity(const Vec3& c, double half_width, double device_radius, double* a,
                         double* b) const override;
  /// The vessel segment nearest to p as `motion` has moved it, among the
  /// primitives listed in p's grid cell: its centreline points and the
  /// parameter t in [0, 1] of its point nearest to p (what the wall's load
  /// at p is shared by). False when the cell lists no segment.
  bool nearestSegment(const Vec3& p, const MotionSnapshot& motion, int* point_a, int* point_b,
                      double* t) const;
  /// Motion periods [s] of the regions (tests).
  std::vector<double> motionPeriods() const;

  double iso() const { return iso_; }
  double alpha() const { return alpha_; }
  int numSegments() const { return static_cast<int>(segments_.size()); }
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }
  double cellSize() const { return cell_; }
  /// Primitives listed in the grid cell of p (diagnostics, benchmarks).
  int primitivesNear(const Vec3& p) const;
  /// Boxes of the grid cells that hold at least one primitive.
  std::vector<Eigen::AlignedBox3d> occupiedCells() const;
  /// Smallest vessel radius [m] (0 without vessels).
  double minRadius() const;

 private:
  struct Segment {
    Vec3 a, b;
    double rho;            // vessel radius [m]
    int weights;           // offset of the endpoints' motion weights (2 * regions)
    Vec3 axis;             // (b - a) / length, at rest
    double length;         // |b - a| at rest [m]
    int point_a, point_b;  // the centreline points at a and b
  };
  struct Sphere {
    Vec3 c;
    double rho;
    int weights;
  };
  Vec3 displaced(const Vec3& x, int weights, int endpoint, const MotionSnapshot& m) const;
  /// A segment moved by a snapshot: its start, unit axis and length [m],
  /// and its radius.
  struct MovedSegment {
    Vec3 a, axis;
    double length;
    double rho;  // the vessel radius as the wall's shape has it [m]
  };
  /// Per thread: the segments moved by the last snapshot this thread used
  /// with this field (vessel_field.cpp).
  struct MovedCache;
  /// This thread's cache, made current for `motion` (once per evaluation,
  /// not per segment: the check compares the whole snapshot).
  MovedCache& movedCache(const MotionSnapshot& motion) const;
  /// Segment id moved by the cache's snapshot, computed once per snapshot.
  const MovedSegment& moved(MovedCache& cache, int id, const MotionSnapshot& motion) const;
  void buildGrid();
  long cellIndex(int ix, int iy, int iz) const {
    return (static_cast<long>(iz) * dims_[1] + iy) * dims_[0] + ix;
  }
  bool cellOf(const Vec3& p, int* ix, int* iy, int* iz) const;
  /// Sum of the Hessian bounds of the primitives listed in cell c.
  double cellHessianBound(long c, double device_radius) const;
  struct HessianTable {
    double device_radius;
    std::vector<float> per_cell;  // cellHessianBound, rounded up
  };

  long serial_{-1};  // unique per constructed field (the moved segments' cache key)
  double alpha_{0.6}, iso_{0.0}, sphere_weight_{0.0}, wall_reach_{0.0};
  std::vector<Segment> segments_;
  std::vector<Sphere> spheres_;
  std::vector<MotionRegion> motion_;
  std::vector<double> motion_weights_;  // per primitive endpoint, per region
  Eigen::AlignedBox3d bounds_;
  double cell_{1e-3};
  int dims_[3]{0, 0, 0};
  std::vector<int> cell_start_;  // CSR over cells
  std::vector<int> cell_items_;  // primitive ids: segments, then spheres (offset)
  std::vector<HessianTable> hessian_tables_;
};

}  // namespace evsim
