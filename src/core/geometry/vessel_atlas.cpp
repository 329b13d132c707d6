// The named vessels of a centreline tree: which vessel a point lies in, how
// deep along it, and the path of vessels between two of them. Declared and
// documented in endovascular_sim/geometry/vessel_atlas.h.
#include "endovascular_sim/geometry/vessel_atlas.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "endovascular_sim/core/edit_distance.h"

namespace evsim {

VesselAtlas::VesselAtlas(const Centerline& centerline) {
  Centerline c = centerline;
  nameVessels(&c);
  const int n = c.numPoints();
  position_ = c.position;
  radius_ = c.radius;
  vessels_.resize(c.vessel_names.size());
  for (size_t v = 0; v < vessels_.size(); ++v) {
    vessels_[v].name = c.vessel_names[v];
    vessels_[v].radius = std::numeric_limits<double>::infinity();
    by_name_[vessels_[v].name] = static_cast<int>(v);
  }

  // Depth of every point along its vessel, parents first (iterative walks).
  std::vector<double> s(n, -1.0);
  for (int i = 0; i < n; ++i) {
    std::vector<int> walk;
    for (int j = i; j >= 0 && s[j] < 0.0; j = c.parent[j]) walk.push_back(j);
    for (auto it = walk.rbegin(); it != walk.rend(); ++it) {
      const int j = *it, p = c.parent[j];
      NamedVessel& v = vessels_[c.vessel[j]];
      if (p < 0) {
        s[j] = 0.0;
        if (v.origin < 0) v.origin = j;
      } else if (c.vessel[p] == c.vessel[j]) {
        s[j] = s[p] + (c.position[j] - c.position[p]).norm();
      } else {
        s[j] = (c.position[j] - c.position[p]).norm();
        if (v.origin < 0) {
          v.origin = p;
          v.parent = c.vessel[p];
          v.origin_depth = s[p];
        }
      }
      v.length = std::max(v.length, s[j]);
      v.radius = std::min(v.radius, c.radius[j]);
    }
  }
  for (size_t v = 0; v < vessels_.size(); ++v) {
    if (vessels_[v].parent >= 0)
      vessels_[vessels_[v].parent].children.push_back(static_cast<int>(v));
    int g = 0;
    for (int p = vessels_[v].parent; p >= 0 && g <= static_cast<int>(vessels_.size());
         p = vessels_[p].parent)
      ++g;
    vessels_[v].generation = g;
  }

  vessel_segments_.resize(vessels_.size());
  double largest = 0.0;
  for (int i = 0; i < n; ++i) {
    const int p = c.parent[i];
    if (p < 0) continue;
    const int v = c.vessel[i];
    segments_.push_back({p, i, v, c.vessel[p] == v ? s[p] : 0.0, s[i]});
    vessel_segments_[v].push_back(static_cast<int>(segments_.size()) - 1);
    largest = std::max({largest, c.radius[i], c.radius[p]});
  }
  for (auto& list : vessel_segments_)
    std::sort(list.begin(), list.end(),
              [&](int a, int b) { return segments_[a].s0 < segments_[b].s0; });

  // A hashed grid: every segment in the cells its box (grown by its radius) touches.
  cell_ = std::max(0.005, largest);
  for (size_t k = 0; k < segments_.size(); ++k) {
    const Segment& g = segments_[k];
    const double r = std::max(radius_[g.a], radius_[g.b]);
    const Vec3 lo = position_[g.a].cwiseMin(position_[g.b]) - Vec3::Constant(r);
    const Vec3 hi = position_[g.a].cwiseMax(position_[g.b]) + Vec3::Constant(r);
    const Eigen::Vector3i a = (lo / cell_).array().floor().cast<int>();
    const Eigen::Vector3i b = (hi / cell_).array().floor().cast<int>();
    for (int z = a.z(); z <= b.z(); ++z)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int x = a.x(); x <= b.x(); ++x)
          grid_[cellKey(cell_ * Vec3(x + 0.5, y + 0.5, z + 0.5))].push_back(static_cast<int>(k));
  }
}

long VesselAtlas::cellKey(const Vec3& p) const {
  const Eigen::Vector3i c = (p / cell_).array().floor().cast<int>();
  return ((static_cast<long>(c.x()) + (1 << 20)) << 42) |
         ((static_cast<long>(c.y()) + (1 << 20)) << 21) | (static_cast<long>(c.z()) + (1 << 20));
}

int VesselAtlas::find(const std::string& name) const {
  const auto it = by_name_.find(name);
  return it == by_name_.end() ? -1 : it->second;
}

std::vector<std::string> VesselAtlas::closestNames(const std::string& name, int count) const {
  std::vector<std::string> names;
  for (const NamedVessel& v : vessels_) names.push_back(v.name);
  return nearestNames(name, names, static_cast<size_t>(std::max(0, count)));
}

const std::vector<int>& VesselAtlas::segmentsNear(const Vec3& p) const {
  static const std::vector<int> kNone;
  const auto it = grid_.find(cellKey(p));
  return it != grid_.end() ? it->second : kNone;
}

VesselLocation VesselAtlas::locate(const Vec3& p) const {
  VesselLocation out;
  if (segments_.empty()) return out;
  struct Hit {
    double radial, depth;
    Vec3 direction;
  };
  auto measure = [&](const Segment& g) {
    const Vec3 a = position_[g.a], d = position_[g.b] - a;
    const double t = std::clamp((p - a).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
    const double r = radius_[g.a] + t * (radius_[g.b] - radius_[g.a]);
    return Hit{(p - a - t * d).norm() / r, g.s0 + t * (g.s1 - g.s0), d.normalized()};
  };
  // The best (smallest radial) hit per vessel among the segments near p:
  // a few vessels meet in a cell, so a short list searched in order (a hash
  // map here was a dozen allocations a step in locateTips).
  std::vector<std::pair<int, Hit>> best;
  best.reserve(8);
  auto find = [&](int v) {
    for (size_t i = 0; i < best.size(); ++i)
      if (best[i].first == v) return static_cast<int>(i);
    return -1;
  };
  auto keep = [&](int v, const Hit& h) {
    const int i = find(v);
    if (i < 0)
      best.emplace_back(v, h);
    else if (h.radial < best[i].second.radial)
      best[i].second = h;
  };
  for (int k : segmentsNear(p)) keep(segments_[k].vessel, measure(segments_[k]));
  int chosen = -1;  // index into best
  for (size_t i = 0; i < best.size(); ++i) {
    const auto& [v, h] = best[i];
    if (h.radial > 1.0) continue;
    const int parent = vessels_[v].parent;
    const int in_parent = parent >= 0 ? find(parent) : -1;
    if (in_parent >= 0 && best[in_parent].second.radial <= 1.0) continue;  // its ostium
    const int c = chosen >= 0 ? best[chosen].first : -1;
    if (chosen < 0 || vessels_[v].generation > vessels_[c].generation ||
        (vessels_[v].generation == vessels_[c].generation && h.radial < best[chosen].second.radial))
      chosen = static_cast<int>(i);
  }
  if (chosen < 0) {  // in no lumen: the nearest vessel, by radial distance
    if (best.empty())
      for (size_t k = 0; k < segments_.size(); ++k)
        keep(segments_[k].vessel, measure(segments_[k]));
    for (size_t i = 0; i < best.size(); ++i)
      if (chosen < 0 || best[i].second.radial < best[chosen].second.radial)
        chosen = static_cast<int>(i);
  }
  const Hit& h = best[chosen].second;
  out.vessel = best[chosen].first;
  out.depth = h.depth;
  out.radial = h.radial;
  out.inside = h.radial <= 1.0;
  out.direction = h.direction;
  return out;
}

VesselLocation VesselAtlas::locateIn(int vessel, const Vec3& p) const {
  VesselLocation out;
  for (int k : vessel_segments_.at(vessel)) {
    const Segment& g = segments_[k];
    const Vec3 a = position_[g.a], d = position_[g.b] - a;
    const double t = std::clamp((p - a).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
    const double r = radius_[g.a] + t * (radius_[g.b] - radius_[g.a]);
    const double radial = (p - a - t * d).norm() / r;
    if (out.vessel >= 0 && radial >= out.radial) continue;
    out.vessel = vessel;
    out.radial = radial;
    out.depth = g.s0 + t * (g.s1 - g.s0);
    out.inside = radial <= 1.0;
    out.direction = d.normalized();
  }
  return out;
}

std::vector<int> VesselAtlas::path(int from, int to) const {
  const int n = static_cast<int>(vessels_.size());
  if (from < 0 || to < 0 || from >= n || to >= n) return {};
  auto ancestors = [&](int v) {
    std::vector<int> chain;
    for (; v >= 0 && static_cast<int>(chain.size()) <= n; v = vessels_[v].parent)
      chain.push_back(v);
    return chain;
  };
  const std::vector<int> up = ancestors(from), down = ancestors(to);
  for (size_t i = 0; i < up.size(); ++i) {
    const auto it = std::find(down.begin(), down.end(), up[i]);
    if (it == down.end()) continue;
    std::vector<int> out(up.begin(), up.begin() + i + 1);
    out.insert(out.end(), std::make_reverse_iterator(it), down.rend());
    return out;
  }
  return {};
}

Vec3 VesselAtlas::pointAt(int vessel, double s, Vec3* direction) const {
  const std::vector<int>& list = vessel_segments_.at(vessel);
  if (list.empty()) {
    if (direction) *direction = Vec3::UnitX();
    return position_[vessels_[vessel].origin];
  }
  const Segment* g = &segments_[list.front()];
  for (int k : list)
    if (segments_[k].s0 <= s) g = &segments_[k];
  const Vec3 a = position_[g->a], d = position_[g->b] - a;
  if (direction) *direction = d.normalized();
  const double t = std::clamp((s - g->s0) / std::max(g->s1 - g->s0, 1e-30), 0.0, 1.0);
  return a + t * d;
}

double VesselAtlas::pathLength(const std::vector<int>& path, double depth,
                               double target_depth) const {
  double remaining = 0.0, s = depth;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const NamedVessel& next = vessels_[path[i + 1]];
    if (next.parent == path[i]) {  // down into a branch
      remaining += std::abs(s - next.origin_depth);
      s = 0.0;
    } else {  // up into the parent
      remaining += s;
      s = vessels_[path[i]].origin_depth;
    }
  }
  return remaining + std::max(0.0, target_depth - s);
}

}  // namespace evsim
