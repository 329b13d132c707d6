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

std::vector<Capsule> capsulesOf(const Centerline& cl, const std::vector<AneurysmSpec>& aneurysms,
                                double margin) {
  std::vector<Capsule> caps;
  for (int i = 0; i < cl.numPoints(); ++i) {
    const int p = cl.parent[i];
    if (p < 0) continue;
    const Vec3 ab = cl.position[i] - cl.position[p];
    const double length = ab.norm();
    if (!(length > 0.0)) continue;
    const double rho = std::max(cl.radius[i], cl.radius[p]);
    caps.push_back({cl.position[p], ab / length, length, rho,
                    VesselProjection::kCapsuleScale * rho + margin, i});
  }
  const size_t segments = caps.size();
  for (const AneurysmSpec& an : aneurysms) {
    // A dome as a zero-length capsule, attributed to the segment nearest it.
    int nearest = -1;
    double best = 1e300;
    for (size_t k = 0; k < segments; ++k) {
      const double d = relativeDistance(caps[k], an.center);
      if (d < best) best = d, nearest = caps[k].segment;
    }
    if (nearest < 0) continue;
    caps.push_back({an.center, Vec3::UnitX(), 0.0, an.radius,
                    VesselProjection::kCapsuleScale * an.radius + margin, nearest});
  }
  return caps;
}

}  // namespace

void VesselProjection::build(const VesselField& field, const Centerline& centerline,
                             const std::vector<AneurysmSpec>& aneurysms, const XrayCamera& camera,
                             int supersampling, const MotionSnapshot& motion, double margin) {
  const int s = std::max(1, supersampling);
  const int rays_per_pixel = s * s;
  const int w = camera.width, h = camera.height;
  const std::vector<Capsule> caps = capsulesOf(centerline, aneurysms, margin);

  // Candidate intervals: each capsule's screen rectangle, ray by ray.
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

  // March the field along each ray's merged intervals.
  evaluations_ = 0;
  auto g = [&](const Vec3& p) {
    ++evaluations_;
    return field.evaluate(p, 0.0, motion).value;
  };
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
    if (pixel_of.empty() || pixel_of.back() != pixel) {
      pixel_of.push_back(pixel);
      per_pixel.emplace_back();
    }
    std::map<int, double>& pieces = per_pixel.back();
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
      // A run of overlapping intervals, and the finest radius among them.
      double t0 = candidates[k].t0, t1 = candidates[k].t1;
      double rho = caps[candidates[k].capsule].rho;
      size_t m = k + 1;
      for (; m < end && candidates[m].t0 <= t1; ++m) {
        t1 = std::max<double>(t1, candidates[m].t1);
        rho = std::min(rho, caps[candidates[m].capsule].rho);
      }
      const double step = 0.5 * rho;
      double ta = t0, ga = g(camera.source + ta * d);
      double enter = ga >= 0.0 ? ta : -1.0;
      while (ta < t1) {
        const double tb = std::min(t1, ta + step);
        const double gb = g(camera.source + tb * d);
        if ((ga >= 0.0) != (gb >= 0.0)) {
          // Illinois on [ta, tb] for the crossing.
          double lo = ta, hi = tb, glo = ga, ghi = gb;
          int side = 0;
          while (hi - lo > kRootTolerance) {
            double t = (lo * ghi - hi * glo) / (ghi - glo);
            if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
            const double gt = g(camera.source + t * d);
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
          const double root = 0.5 * (lo + hi);
          if (gb >= 0.0) {
            enter = root;
          } else if (enter >= 0.0) {
            attribute(enter, root);
            enter = -1.0;
          }
        }
        ta = tb, ga = gb;
      }
      if (enter >= 0.0) attribute(enter, t1);  // the bound ended inside (should not happen)
      k = m;
    }
    i = end;
  }

  offset_.assign(static_cast<size_t>(w) * h + 1, 0);
  pieces_.clear();
  size_t next = 0;
  for (long p = 0; p < static_cast<long>(w) * h; ++p) {
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
