// The lumen as X-rays cross it. Declared and documented in
// endovascular_sim/imaging/vessel_projection.h.
#include "endovascular_sim/imaging/vessel_projection.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "endovascular_sim/imaging/ray_geometry.h"

namespace evsim {

namespace {

struct Capsule {
  Vec3 a, u;      // start and unit axis
  double length;  // [m]
  double rho;     // vessel radius [m]
  double bound;   // capsule radius [m]
  int segment;    // centreline point it is attributed to
};

struct Candidate {
  long ray;  // pixel * s^2 + sub-ray
  float t0, t1;
  int capsule;
};

/// Distance from p to the capsule's axis over its radius.
double relativeDistance(const Capsule& c, const Vec3& p) {
  const double s = std::clamp((p - c.a).dot(c.u), 0.0, c.length);
  return (c.a + s * c.u - p).norm() / c.rho;
}

/// The segments' bounding capsules where `motion` has moved them: the field
/// moves each segment's end points by the motion's displacement there
/// (vessel_field.h), and so do the capsules.
std::vector<Capsule> capsulesOf(const VesselField& field, const Centerline& cl,
                                const std::vector<AneurysmSpec>& aneurysms,
                                const MotionSnapshot& motion, double margin) {
  auto at = [&](const Vec3& x) -> Vec3 {
    return motion.empty() ? x : Vec3(x + field.displacement(x, motion));
  };
  std::vector<Vec3> position(cl.position.size());
  for (size_t i = 0; i < position.size(); ++i) position[i] = at(cl.position[i]);
  std::vector<Capsule> caps;
  for (int i = 0; i < cl.numPoints(); ++i) {
    const int p = cl.parent[i];
    if (p < 0) continue;
    const Vec3 ab = position[i] - position[p];
    const double length = ab.norm();
    if (!(length > 0.0)) continue;
    const double rho = std::max(cl.radius[i], cl.radius[p]);
    caps.push_back(
        {position[p], ab / length, length, rho, VesselProjection::kCapsuleScale * rho + margin, i});
  }
  const size_t segments = caps.size();
  for (const AneurysmSpec& an : aneurysms) {
    // A dome as a zero-length capsule, attributed to the segment nearest it.
    int nearest = -1;
    double best = 1e300;
    for (size_t k = 0; k < segments; ++k) {
      const double d = relativeDistance(caps[k], at(an.center));
      if (d < best) best = d, nearest = caps[k].segment;
    }
    if (nearest < 0) continue;
    caps.push_back({at(an.center), Vec3::UnitX(), 0.0, an.radius,
                    VesselProjection::kCapsuleScale * an.radius + margin, nearest});
  }
  return caps;
}

/// The capsules of the wanted segments and of every capsule whose box
/// touches one of theirs (the rest of the tree cannot share a ray's
/// interval with a wanted capsule).
std::vector<Capsule> wantedCapsules(std::vector<Capsule> caps, const std::vector<char>& only) {
  using Box = Eigen::AlignedBox3d;
  auto boxOf = [](const Capsule& c) {
    Box b(c.a);
    b.extend(c.a + c.length * c.u);
    return Box(b.min().array() - c.bound, b.max().array() + c.bound);
  };
  std::vector<Box> wanted;
  for (const Capsule& c : caps)
    if (c.segment < static_cast<int>(only.size()) && only[c.segment]) wanted.push_back(boxOf(c));
  Box all;
  for (const Box& b : wanted) all.extend(b);
  std::vector<Capsule> kept;
  for (const Capsule& c : caps) {
    const Box b = boxOf(c);
    if (!all.intersects(b)) continue;
    for (const Box& w : wanted)
      if (w.intersects(b)) {
        kept.push_back(c);
        break;
      }
  }
  return kept;
}

/// Each capsule's screen rectangle, ray by ray (s x s sub-rays per pixel):
/// the intervals of each ray inside a capsule, sorted by ray and entry.
std::vector<Candidate> candidatesOf(const std::vector<Capsule>& caps, const XrayCamera& camera,
                                    int s) {
  const int rays_per_pixel = s * s, w = camera.width, h = camera.height;
  std::vector<Candidate> candidates;
  for (int k = 0; k < static_cast<int>(caps.size()); ++k) {
    const Capsule& c = caps[k];
    const Vec3 pa = camera.project(c.a), pb = camera.project(c.a + c.length * c.u);
    const double near = std::min(pa.z(), pb.z()) - c.bound;
    if (!(near > 0.0)) continue;  // behind the source
    const double grow = c.bound * camera.fx / near + 1.0;
    const int u0 = std::max(0, static_cast<int>(std::floor(std::min(pa.x(), pb.x()) - grow)));
    const int u1 = std::min(w - 1, static_cast<int>(std::ceil(std::max(pa.x(), pb.x()) + grow)));
    const int v0 = std::max(0, static_cast<int>(std::floor(std::min(pa.y(), pb.y()) - grow)));
    const int v1 = std::min(h - 1, static_cast<int>(std::ceil(std::max(pa.y(), pb.y()) + grow)));
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u)
        for (int j = 0; j < rays_per_pixel; ++j) {
          const double du = (j % s + 0.5) / s - 0.5, dv = (j / s + 0.5) / s - 0.5;
          const Vec3 d = camera.ray(u + du, v + dv);
          const RayInterval in =
              rayInCylinder(camera.source, d, c.a, c.u, c.bound, -c.bound, c.length + c.bound);
          if (in.empty()) continue;
          candidates.push_back({(static_cast<long>(v) * w + u) * rays_per_pixel + j,
                                static_cast<float>(in.t0), static_cast<float>(in.t1), k});
        }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.ray < b.ray || (a.ray == b.ray && a.t0 < b.t0);
  });
  return candidates;
}

/// The wall's crossing on [lo, hi] of a ray, where g(t) changes sign:
/// Illinois to kRootTolerance.
template <typename G>
double wallCrossing(const G& g, double lo, double hi, double glo, double ghi) {
  int side = 0;
  while (hi - lo > VesselProjection::kRootTolerance) {
    double t = (lo * ghi - hi * glo) / (ghi - glo);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
    const double gt = g(t);
    if ((gt >= 0.0) == (glo >= 0.0)) {
      lo = t, glo = gt;
      if (side == -1) ghi *= 0.5;
      side = -1;
    } else {
      hi = t, ghi = gt;
      if (side == 1) glo *= 0.5;
      side = 1;
    }
  }
  return 0.5 * (lo + hi);
}

/// Calls inside(enter, leave) for each stretch of [t0, t1] where g >= 0
/// (the lumen), marching by `step` and refining each crossing.
template <typename G, typename F>
void lumenStretches(const G& g, double t0, double t1, double step, F&& inside) {
  double ta = t0, ga = g(ta);
  double enter = ga >= 0.0 ? ta : -1.0;
  while (ta < t1) {
    const double tb = std::min(t1, ta + step);
    const double gb = g(tb);
    if ((ga >= 0.0) != (gb >= 0.0)) {
      const double root = wallCrossing(g, ta, tb, ga, gb);
      if (gb >= 0.0) {
        enter = root;
      } else if (enter >= 0.0) {
        inside(enter, root);
        enter = -1.0;
      }
    }
    ta = tb, ga = gb;
  }
  if (enter >= 0.0) inside(enter, t1);  // the bound ended inside (should not happen)
}

}  // namespace

void VesselProjection::build(const VesselField& field, const Centerline& centerline,
                             const std::vector<AneurysmSpec>& aneurysms, const XrayCamera& camera,
                             int supersampling, const MotionSnapshot& motion, double margin,
                             const std::vector<char>* only) {
  const int s = std::max(1, supersampling);
  const int rays_per_pixel = s * s;
  const int w = camera.width;
  const std::vector<Capsule> caps =
      only ? wantedCapsules(capsulesOf(field, centerline, aneurysms, motion, margin), *only)
           : capsulesOf(field, centerline, aneurysms, motion, margin);
  const std::vector<Candidate> candidates = candidatesOf(caps, camera, s);

  // March the field along each ray's merged intervals.
  evaluations_ = 0;
  std::vector<std::map<int, double>> per_pixel;  // only pixels with candidates
  std::vector<long> pixel_of;
  const double weight = 1.0 / rays_per_pixel;
  size_t i = 0;
  while (i < candidates.size()) {
    const long ray = candidates[i].ray;
    size_t end = i;
    while (end < candidates.size() && candidates[end].ray == ray) ++end;
    const long pixel = ray / rays_per_pixel;
    const int j = static_cast<int>(ray % rays_per_pixel);
    const Vec3 d =
        camera.ray(pixel % w + ((j % s + 0.5) / s - 0.5), pixel / w + ((j / s + 0.5) / s - 0.5));
    auto g = [&](double t) {
      ++evaluations_;
      return field.evaluate(camera.source + t * d, 0.0, motion).value;
    };
    if (pixel_of.empty() || pixel_of.back() != pixel) {
      pixel_of.push_back(pixel);
      per_pixel.emplace_back();
    }
    std::map<int, double>& pieces = per_pixel.back();
    // A stretch inside goes to the segment of the capsule nearest its middle.
    auto attribute = [&](double ta, double tb) {
      const Vec3 mid = camera.source + 0.5 * (ta + tb) * d;
      int best = candidates[i].capsule;
      double best_d = 1e300;
      for (size_t k = i; k < end; ++k) {
        const double dist = relativeDistance(caps[candidates[k].capsule], mid);
        if (dist < best_d) best_d = dist, best = candidates[k].capsule;
      }
      pieces[caps[best].segment] += (tb - ta) * weight;
    };
    for (size_t k = i; k < end;) {
      // A run of overlapping intervals, marched at half the finest radius among them.
      double t1 = candidates[k].t1;
      double rho = caps[candidates[k].capsule].rho;
      size_t m = k + 1;
      for (; m < end && candidates[m].t0 <= t1; ++m) {
        t1 = std::max<double>(t1, candidates[m].t1);
        rho = std::min(rho, caps[candidates[m].capsule].rho);
      }
      lumenStretches(g, candidates[k].t0, t1, 0.5 * rho, attribute);
      k = m;
    }
    i = end;
  }
  pack(per_pixel, pixel_of, static_cast<long>(w) * camera.height);
}

void VesselProjection::pack(const std::vector<std::map<int, double>>& per_pixel,
                            const std::vector<long>& pixel_of, long pixels) {
  offset_.assign(static_cast<size_t>(pixels) + 1, 0);
  pieces_.clear();
  size_t next = 0;
  for (long p = 0; p < pixels; ++p) {
    offset_[p] = static_cast<long>(pieces_.size());
    if (next < pixel_of.size() && pixel_of[next] == p) {
      for (const auto& [segment, length] : per_pixel[next])
        if (length > 0.0) pieces_.push_back({segment, static_cast<float>(length)});
      ++next;
    }
  }
  offset_.back() = static_cast<long>(pieces_.size());
}

void VesselProjection::addAttenuation(const std::vector<double>& mu,
                                      std::vector<float>* image) const {
  for (size_t p = 0; p + 1 < offset_.size(); ++p) {
    double a = 0.0;
    for (long k = offset_[p]; k < offset_[p + 1]; ++k)
      a += pieces_[k].length * mu[pieces_[k].segment];
    if (a != 0.0) (*image)[p] += static_cast<float>(a);
  }
}

double VesselProjection::pathLength(int pixel) const {
  double length = 0.0;
  for (long k = offset_[pixel]; k < offset_[pixel + 1]; ++k) length += pieces_[k].length;
  return length;
}

}  // namespace evsim
