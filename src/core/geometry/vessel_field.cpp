// The implicit vessel surface: a convolution field of centreline segments (and
// aneurysm spheres), indexed by a uniform grid over their supports. Declared
// and documented in endovascular_sim/geometry/vessel_field.h.
#include "endovascular_sim/geometry/vessel_field.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "endovascular_sim/core/thread_cache.h"

namespace evsim {
namespace {

double falloff(double s) { return s < 1.0 ? (1.0 - s * s) * (1.0 - s * s) : 0.0; }

/// Distance from the segment [a, b] to an axis-aligned box [m]: the
/// distance to the box along the segment is convex in the segment's
/// parameter, so a golden-section search finds its minimum (to 1e-6 of the
/// segment's length: the grid only needs it to the support's precision).
double segmentBoxDistance(const Vec3& a, const Vec3& b, const Eigen::AlignedBox3d& box) {
  auto distance = [&](double t) { return box.exteriorDistance(a + t * (b - a)); };
  constexpr double kGolden = 0.6180339887498949;
  double lo = 0.0, hi = 1.0;
  double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
  double f1 = distance(x1), f2 = distance(x2);
  for (int i = 0; i < 30 && std::max(f1, f2) > 0.0; ++i) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kGolden * (hi - lo);
      f1 = distance(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kGolden * (hi - lo);
      f2 = distance(x2);
    }
  }
  return std::min({f1, f2, distance(0.0), distance(1.0)});
}

}  // namespace

VesselField::VesselField(const Centerline& centerline, const std::vector<AneurysmSpec>& aneurysms,
                         const std::vector<MotionRegion>& motion, const VesselFieldOptions& options)
    : alpha_(options.alpha), wall_reach_(options.wall_reach), motion_(motion) {
  static std::atomic<long> serials{0};
  serial_ = serials++;
  if (!(alpha_ > 0.0 && alpha_ < 1.0)) throw std::invalid_argument("alpha must lie in (0, 1)");
  if (!(wall_reach_ >= 0.0)) throw std::invalid_argument("wall_reach must not be negative");
  iso_ = isoValueForAlpha(alpha_);
  sphere_weight_ = iso_ / std::pow(1.0 - alpha_ * alpha_, 3);
  const int nr = static_cast<int>(motion_.size());
  auto addWeights = [&](const Vec3& x) {
    for (const auto& r : motion_)
      motion_weights_.push_back(falloff((x - r.center).norm() / r.radius));
  };
  for (int i = 0; i < centerline.numPoints(); ++i) {
    const int p = centerline.parent[i];
    if (p < 0) continue;
    Segment s{centerline.position[p],
              centerline.position[i],
              0.5 * (centerline.radius[p] + centerline.radius[i]),
              static_cast<int>(motion_weights_.size()),
              Vec3::Zero(),
              0.0,
              p,
              i};
    const Vec3 ab = s.b - s.a;
    s.length = ab.norm();
    if (s.length > 0.0) s.axis = ab / s.length;
    if (nr) {
      addWeights(s.a);
      addWeights(s.b);
    }
    segments_.push_back(s);
  }
  for (const auto& a : aneurysms) {
    spheres_.push_back({a.center, a.radius, static_cast<int>(motion_weights_.size())});
    if (nr) {
      addWeights(a.center);
      addWeights(a.center);
    }
  }
  buildGrid();
}

Vec3 VesselField::displaced(const Vec3& x, int weights, int endpoint,
                            const MotionSnapshot& m) const {
  if (m.regions.empty()) return x;
  Vec3 y = x;
  const double* w = &motion_weights_[weights + endpoint * motion_.size()];
  for (size_t k = 0; k < m.regions.size(); ++k) y += w[k] * m.regions[k];
  return y;
}

struct VesselField::MovedCache {
  long field{-1};  // serial_ of the field (an address may be reused by another)
  MotionSnapshot motion;
  unsigned epoch{0};
  std::vector<unsigned> stamp;
  std::vector<MovedSegment> segments;
};

VesselField::MovedCache& VesselField::movedCache(const MotionSnapshot& motion) const {
  // Per thread, so that the model stays shareable between threads stepping
  // their own data.
  MovedCache& cache = threadCache<MovedCache>();
  if (cache.field != serial_ || cache.motion != motion) {
    cache.field = serial_;
    cache.motion = motion;
    if (++cache.epoch == 0 || cache.stamp.size() != segments_.size()) {
      cache.stamp.assign(segments_.size(), 0);
      cache.segments.resize(segments_.size());
      cache.epoch = 1;
    }
  }
  return cache;
}

const VesselField::MovedSegment& VesselField::moved(MovedCache& cache, int id,
                                                    const MotionSnapshot& motion) const {
  MovedSegment& m = cache.segments[id];
  if (cache.stamp[id] != cache.epoch) {
    const Segment& s = segments_[id];
    m.a = displaced(s.a, s.weights, 0, motion);
    Vec3 b = displaced(s.b, s.weights, 1, motion);
    m.rho = s.rho;
    if (motion.wall) {  // the skeleton's points moved, the radii changed
      const WallShape& w = *motion.wall;
      m.a += w.displacement[s.point_a];
      b += w.displacement[s.point_b];
      m.rho += 0.5 * (w.radius_change[s.point_a] + w.radius_change[s.point_b]);
    }
    const Vec3 ab = b - m.a;
    m.length = ab.norm();  // the same arithmetic as addSegmentField's
    m.axis = m.length > 0.0 ? Vec3(ab / m.length) : Vec3::Zero();
    cache.stamp[id] = cache.epoch;
  }
  return m;
}

Vec3 VesselField::displacement(const Vec3& x, const MotionSnapshot& m) const {
  Vec3 u = Vec3::Zero();
  for (size_t k = 0; k < m.regions.size() && k < motion_.size(); ++k)
    u += falloff((x - motion_[k].center).norm() / motion_[k].radius) * m.regions[k];
  return u;
}

Vec3 VesselField::displacementChange(const Vec3& x, const std::vector<Vec3>& m0,
                                     const std::vector<Vec3>& m1) const {
  Vec3 du = Vec3::Zero();
  for (size_t k = 0; k < motion_.size() && k < m0.size() && k < m1.size(); ++k)
    du += falloff((x - motion_[k].center).norm() / motion_[k].radius) * (m1[k] - m0[k]);
  return du;
}

double VesselField::deformationRate(const std::vector<Vec3>& m0,
                                    const std::vector<Vec3>& m1) const {
  // |falloff'(s)| = 4 s (1 - s^2) <= 8 / (3 sqrt 3) = 1.5396 (at s^2 = 1/3):
  // two points of one region's weights differ by at most that over its
  // radius per metre between them (rounded up).
  constexpr double kFalloffSlope = 1.5397;
  double kappa = 0.0;
  for (size_t k = 0; k < motion_.size() && k < m0.size() && k < m1.size(); ++k)
    kappa += kFalloffSlope / motion_[k].radius * (m1[k] - m0[k]).norm();
  return kappa;
}

bool VesselField::motionSensitivity(const Vec3& c, double half_width, double device_radius,
                                    double* a, double* b) const {
  // A segment's field (1/R) int K(|q - x(t)|) dt whose points move by at
  // most delta: its length changes by at most 2 delta against an integral
  // of K of at most 1 (times 1/R), and K, whose slope is at most 1.7173 /
  // R (at r^2 = R^2 / 5), changes by at most that times delta over the
  // stretch within R + delta of q (2 (R + delta) long): |df| <= (2 +
  // 3.4346) delta / R + 3.4346 delta^2 / R^2. A sphere: w 1.7173 delta / R.
  // With delta = kappa d, d the farthest of its (rest) endpoints from c.
  // Summed once per eighth of a grid cell for every centre in it (d from
  // its farthest corner, the primitives of the cells its box grown by
  // half_width meets) and kept per thread: the balls of a device sliding
  // through a lumen fall in few of them.
  *a = *b = 0.0;
  int ix, iy, iz;
  if (!cellOf(c, &ix, &iy, &iz)) return true;  // no primitive: g does not change
  struct Entry {
    double half_width{-1.0}, a{0.0}, b{0.0};
  };
  struct HessianCache {
    long field{-1};
    std::vector<std::pair<double, std::unordered_map<long, Entry>>> per_radius;
    std::vector<int> ids;
    std::vector<unsigned> seen;  // per primitive: the miss that listed it last
    unsigned miss{0};
    // In front of the maps, the entries asked for lately, direct-mapped by
    // cell (a device's balls fall in a few hundred cells; a hash lookup in
    // a map of tens of thousands missed the caches).
    struct Recent {
      long cell{-1};
      double radius{-1.0};
      Entry* entry{nullptr};  // (a map's entries stay where they are)
    };
    std::array<Recent, 1024> recent;
  };
  HessianCache& cache = threadCache<HessianCache>();
  if (cache.field != serial_) {
    cache.field = serial_;
    cache.per_radius.clear();
    cache.seen.assign(segments_.size() + spheres_.size(), 0);
    cache.miss = 0;
    cache.recent.fill({});
  }
  // Per eighth of a grid cell: d from its farthest corner.
  const double part = 0.5 * cell_;
  int sub[3];
  for (int k = 0; k < 3; ++k)
    sub[k] = std::clamp(static_cast<int>((c[k] - bounds_.min()[k]) / part), 0, 2 * dims_[k] - 1);
  const long cell = (static_cast<long>(sub[2]) * 2 * dims_[1] + sub[1]) * 2 * dims_[0] + sub[0];
  auto& recent = cache.recent[static_cast<size_t>(cell) % cache.recent.size()];
  if (!recent.entry || recent.cell != cell || recent.radius != device_radius) {
    std::unordered_map<long, Entry>* cells = nullptr;
    for (auto& r : cache.per_radius)
      if (r.first == device_radius) cells = &r.second;
    if (!cells)
      cells =
          &cache.per_radius.emplace_back(device_radius, std::unordered_map<long, Entry>{}).second;
    recent = {cell, device_radius, &(*cells)[cell]};
  }
  Entry& e = *recent.entry;
  if (e.half_width < half_width) {
    const Vec3 lo = bounds_.min() + part * Vec3(sub[0], sub[1], sub[2]);
    const Vec3 hi = lo + Vec3::Constant(part);
    int from[3], to[3];
    for (int k = 0; k < 3; ++k) {
      from[k] =
          std::clamp(static_cast<int>(std::floor((lo[k] - half_width - bounds_.min()[k]) / cell_)),
                     0, dims_[k] - 1);
      to[k] =
          std::clamp(static_cast<int>(std::floor((hi[k] + half_width - bounds_.min()[k]) / cell_)),
                     0, dims_[k] - 1);
    }
    // Each primitive once (a box of 4^3 cells lists a few hundred items for
    // a dozen primitives): marked with this miss's number, and only those sorted.
    if (++cache.miss == 0) {
      std::fill(cache.seen.begin(), cache.seen.end(), 0u);
      cache.miss = 1;
    }
    std::vector<int>& ids = cache.ids;
    ids.clear();
    unsigned* const seen = cache.seen.data();
    const unsigned miss = cache.miss;
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y)
        for (int x = from[0]; x <= to[0]; ++x) {
          const long n = cellIndex(x, y, z);
          for (int k = cell_start_[n]; k < cell_start_[n + 1]; ++k) {
            const int id = cell_items_[k];
            if (seen[id] == miss) continue;
            seen[id] = miss;
            ids.push_back(id);
          }
        }
    std::sort(ids.begin(), ids.end());    // (the sums in the primitives' order)
    auto farthest = [&](const Vec3& p) {  // from p to the cell's farthest point
      return (p - lo).cwiseAbs().cwiseMax((p - hi).cwiseAbs()).norm();
    };
    const int ns = static_cast<int>(segments_.size());
    e = Entry{half_width, 0.0, 0.0};
    for (int id : ids) {
      if (id < ns) {
        const Segment& s = segments_[id];
        const double R = (s.rho - device_radius) / alpha_;
        if (R <= 0.0) continue;
        const double d = std::max(farthest(s.a), farthest(s.b)) / R;
        e.a += 5.4347 * d;
        e.b += 3.4347 * d * d;
      } else {
        const Sphere& s = spheres_[id - ns];
        const double R = (s.rho - device_radius) / alpha_;
        if (R <= 0.0) continue;
        e.a += 1.7174 * sphere_weight_ * farthest(s.c) / R;
      }
    }
  }
  *a = e.a;
  *b = e.b;
  return true;
}

MotionSnapshot VesselField::motionAt(double t) const {
  MotionSnapshot m;
  for (const auto& r : motion_)
    m.regions.push_back(r.amplitude * std::sin(2.0 * M_PI * r.frequency * t + r.phase));
  return m;
}

std::vector<double> VesselField::motionPeriods() const {
  std::vector<double> p;
  for (const auto& r : motion_) p.push_back(1.0 / r.frequency);
  return p;
}

void VesselField::buildGrid() {
  // Support boxes (largest width: device radius 0), grown by the motion.
  std::vector<Eigen::AlignedBox3d> boxes;
  std::vector<double> support;
  const int nr = static_cast<int>(motion_.size());
  auto reach = [&](int weights, int endpoint) {
    double d = 0.0;
    for (int k = 0; k < nr; ++k)
      d += motion_weights_[weights + endpoint * nr + k] * motion_[k].amplitude.norm();
    return d;
  };
  for (const auto& s : segments_) {
    // (a wall that gives way moves the points by at most wall_reach_ and
    // widens the kernel by at most wall_reach_ / alpha_)
    const double R = s.rho / alpha_ + std::max(reach(s.weights, 0), reach(s.weights, 1)) +
                     wall_reach_ * (1.0 + 1.0 / alpha_);
    Eigen::AlignedBox3d b(s.a.cwiseMin(s.b), s.a.cwiseMax(s.b));
    boxes.emplace_back(b.min() - Vec3::Constant(R), b.max() + Vec3::Constant(R));
    support.push_back(R);
  }
  for (const auto& s : spheres_) {
    const double R = s.rho / alpha_ + reach(s.weights, 0);
    boxes.emplace_back(s.c - Vec3::Constant(R), s.c + Vec3::Constant(R));
    support.push_back(R);
  }
  bounds_.setEmpty();
  for (const auto& b : boxes) bounds_.extend(b);
  if (boxes.empty()) return;
  std::vector<double> sorted = support;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const Vec3 extent = bounds_.sizes();
  cell_ = std::max(sorted[sorted.size() / 2], extent.maxCoeff() / 256.0);
  for (int k = 0; k < 3; ++k)
    dims_[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / cell_)));
  const long cells = static_cast<long>(dims_[0]) * dims_[1] * dims_[2];

  // Two passes: count, then fill (CSR).
  cell_start_.assign(cells + 1, 0);
  auto forCells = [&](const Eigen::AlignedBox3d& b, auto&& fn) {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] =
          std::clamp(static_cast<int>((b.min()[k] - bounds_.min()[k]) / cell_), 0, dims_[k] - 1);
      hi[k] =
          std::clamp(static_cast<int>((b.max()[k] - bounds_.min()[k]) / cell_), 0, dims_[k] - 1);
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) fn(cellIndex(x, y, z));
  };
  // A primitive is listed in a cell only where its support reaches the
  // cell (not wherever its bounding box does): a wide aortic segment's box
  // covers the branches' cells that its support never reaches. The field
  // is the same, its evaluation and Hessian bound cheaper.
  const int ns = static_cast<int>(segments_.size());
  auto reaches = [&](int i, long c) {
    const int iz = static_cast<int>(c / (static_cast<long>(dims_[0]) * dims_[1]));
    const int iy = static_cast<int>((c / dims_[0]) % dims_[1]);
    const int ix = static_cast<int>(c % dims_[0]);
    const Eigen::AlignedBox3d cell(bounds_.min() + cell_ * Vec3(ix, iy, iz),
                                   bounds_.min() + cell_ * Vec3(ix + 1, iy + 1, iz + 1));
    const double d = i < ns ? segmentBoxDistance(segments_[i].a, segments_[i].b, cell)
                            : cell.exteriorDistance(spheres_[i - ns].c);
    return d < support[i] * (1.0 + 1e-9);
  };
  std::vector<std::vector<long>> cells_of(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i)
    forCells(boxes[i], [&](long c) {
      if (reaches(static_cast<int>(i), c)) cells_of[i].push_back(c);
    });
  for (const auto& list : cells_of)
    for (long c : list) ++cell_start_[c + 1];
  for (long c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_items_.resize(cell_start_[cells]);
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < boxes.size(); ++i)
    for (long c : cells_of[i]) cell_items_[fill[c]++] = static_cast<int>(i);
}

bool VesselField::cellOf(const Vec3& p, int* ix, int* iy, int* iz) const {
  if (cell_start_.empty() || !bounds_.contains(p)) return false;
  const Vec3 q = (p - bounds_.min()) / cell_;
  *ix = std::min(static_cast<int>(q.x()), dims_[0] - 1);
  *iy = std::min(static_cast<int>(q.y()), dims_[1] - 1);
  *iz = std::min(static_cast<int>(q.z()), dims_[2] - 1);
  return true;
}

int VesselField::primitivesNear(const Vec3& p) const {
  int x, y, z;
  if (!cellOf(p, &x, &y, &z)) return 0;
  const long c = cellIndex(x, y, z);
  return cell_start_[c + 1] - cell_start_[c];
}

std::vector<Eigen::AlignedBox3d> VesselField::occupiedCells() const {
  std::vector<Eigen::AlignedBox3d> cells;
  for (int z = 0; z < dims_[2]; ++z)
    for (int y = 0; y < dims_[1]; ++y)
      for (int x = 0; x < dims_[0]; ++x) {
        const long c = cellIndex(x, y, z);
        if (cell_start_[c + 1] == cell_start_[c]) continue;
        // Both corners from the integer index: neighbours share the bits.
        cells.emplace_back(bounds_.min() + cell_ * Vec3(x, y, z),
                           bounds_.min() + cell_ * Vec3(x + 1, y + 1, z + 1));
      }
  return cells;
}

double VesselField::minRadius() const {
  double r = segments_.empty() && spheres_.empty() ? 0.0 : 1e9;
  for (const auto& s : segments_) r = std::min(r, s.rho);
  for (const auto& s : spheres_) r = std::min(r, s.rho);
  return r;
}

FieldSample VesselField::evaluate(const Vec3& p, double device_radius,
                                  const MotionSnapshot& motion) const {
  FieldSample out;
  int x, y, z;
  if (cellOf(p, &x, &y, &z)) {
    const long c = cellIndex(x, y, z);
    const int ns = static_cast<int>(segments_.size());
    MovedCache* cache = motion.empty() ? nullptr : &movedCache(motion);
    for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      const int id = cell_items_[k];
      if (id < ns) {
        const Segment& s = segments_[id];
        if (motion.empty()) {  // at rest: the axis and length kept
          const double R = (s.rho - device_radius) / alpha_;
          if (R > 0.0 && s.length > 0.0) addSegmentFieldAlong(s.a, s.axis, s.length, R, p, &out);
        } else {
          const MovedSegment& m = moved(*cache, id, motion);
          const double R = (m.rho - device_radius) / alpha_;
          if (R > 0.0 && m.length > 0.0) addSegmentFieldAlong(m.a, m.axis, m.length, R, p, &out);
        }
      } else {
        const Sphere& s = spheres_[id - ns];
        const double R = (s.rho - device_radius) / alpha_;
        if (R <= 0.0) continue;
        addSphereField(displaced(s.c, s.weights, 0, motion), R, sphere_weight_, p, &out);
      }
    }
  }
  out.value -= iso_;
  return out;
}

bool VesselField::nearestSegment(const Vec3& p, const MotionSnapshot& motion, int* point_a,
                                 int* point_b, double* t) const {
  int x, y, z;
  if (!cellOf(p, &x, &y, &z)) return false;
  const long c = cellIndex(x, y, z);
  const int ns = static_cast<int>(segments_.size());
  MovedCache* cache = motion.empty() ? nullptr : &movedCache(motion);
  double best = std::numeric_limits<double>::infinity();
  for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
    const int id = cell_items_[k];
    if (id >= ns) continue;
    const Segment& s = segments_[id];
    Vec3 a = s.a, axis = s.axis;
    double length = s.length;
    if (cache) {
      const MovedSegment& m = moved(*cache, id, motion);
      a = m.a;
      axis = m.axis;
      length = m.length;
    }
    const double along = std::clamp((p - a).dot(axis), 0.0, length);
    const double d = (p - a - along * axis).squaredNorm();
    if (d < best) {
      best = d;
      *point_a = s.point_a;
      *point_b = s.point_b;
      *t = length > 0.0 ? along / length : 0.0;
    }
  }
  return best < std::numeric_limits<double>::infinity();
}

double VesselField::cellHessianBound(long c, double device_radius) const {
  const int ns = static_cast<int>(segments_.size());
  double sum = 0.0;
  for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
    const int id = cell_items_[k];
    const double rho = id < ns ? segments_[id].rho : spheres_[id - ns].rho;
    const double R = (rho - device_radius) / alpha_;
    if (R <= 0.0) continue;
    sum += id < ns ? segmentHessianBound(R) : sphereHessianBound(R, sphere_weight_);
  }
  return sum;
}

void VesselField::tabulateHessianBounds(const std::vector<double>& device_radii) {
  const long cells = static_cast<long>(cell_start_.size()) - 1;
  if (cells <= 0 || cells > kMaxTabulatedCells) return;
  for (double r : device_radii) {
    bool known = false;
    for (const HessianTable& t : hessian_tables_) known = known || t.device_radius == r;
    if (known) continue;
    HessianTable table{r, std::vector<float>(cells, 0.0f)};
    for (long c = 0; c < cells; ++c) {
      const double sum = cellHessianBound(c, r);
      float v = static_cast<float>(sum);
      if (static_cast<double>(v) < sum)
        v = std::nextafter(v, std::numeric_limits<float>::infinity());
      table.per_cell[c] = v;
    }
    hessian_tables_.push_back(std::move(table));
  }
}

double VesselField::hessianBound(const Vec3& p0, const Vec3& p1, double device_radius) const {
  if (cell_start_.empty()) return 0.0;
  int lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const double a = (std::min(p0[k], p1[k]) - bounds_.min()[k]) / cell_;
    const double b = (std::max(p0[k], p1[k]) - bounds_.min()[k]) / cell_;
    lo[k] = std::clamp(static_cast<int>(std::floor(a)), 0, dims_[k] - 1);
    hi[k] = std::clamp(static_cast<int>(std::floor(b)), 0, dims_[k] - 1);
  }
  const std::vector<float>* table = nullptr;
  for (const HessianTable& t : hessian_tables_)
    if (t.device_radius == device_radius) table = &t.per_cell;
  double bound = 0.0;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const long c = cellIndex(x, y, z);
        bound = std::max(
            bound, table ? static_cast<double>((*table)[c]) : cellHessianBound(c, device_radius));
      }
  return bound;
}

}  // namespace evsim
