// A deterministic generator of large vascular networks. Declared and
// documented in endovascular_sim/geometry/network_generator.h.
#include "endovascular_sim/geometry/network_generator.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <random>
#include <unordered_map>

namespace evsim {
namespace {

class Uniform {
 public:
  explicit Uniform(uint64_t seed) : rng_(seed) {}
  double operator()() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  double between(double a, double b) { return a + (b - a) * (*this)(); }

 private:
  std::mt19937_64 rng_;
};

/// Segments of the network hashed by their midpoints, for proximity checks.
class SegmentHash {
 public:
  explicit SegmentHash(double cell) : cell_(cell) {}
  void add(const Vec3& a, const Vec3& b, double r, int vessel) {
    const int id = static_cast<int>(segs_.size());
    segs_.push_back({a, b, r, vessel});
    cells_[cellKey(cellOf(0.5 * (a + b)))].push_back(id);
  }
  /// True when [a, b] (radius r) comes closer than the radii to a segment of
  /// a vessel not in `ignore`.
  bool collides(const Vec3& a, const Vec3& b, double r, int ignore1, int ignore2) const {
    const Vec3 m = 0.5 * (a + b);
    const int reach = 1 + static_cast<int>((0.5 * (b - a).norm() + 2 * r) / cell_);
    const Eigen::Vector3i c = cellOf(m);
    for (int dz = -reach; dz <= reach; ++dz)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const auto it = cells_.find(cellKey(Eigen::Vector3i(c + Eigen::Vector3i(dx, dy, dz))));
          if (it == cells_.end()) continue;
          for (int id : it->second) {
            const Seg& s = segs_[id];
            if (s.vessel == ignore1 || s.vessel == ignore2) continue;
            if (distance(a, b, s.a, s.b) < r + s.r) return true;
          }
        }
    return false;
  }

 private:
  struct Seg {
    Vec3 a, b;
    double r;
    int vessel;
  };
  Eigen::Vector3i cellOf(const Vec3& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell_)),
                           static_cast<int>(std::floor(p.y() / cell_)),
                           static_cast<int>(std::floor(p.z() / cell_)));
  }
  static int64_t cellKey(const Eigen::Vector3i& c) {
    return (static_cast<int64_t>(c.x() + (1 << 20)) << 42) |
           (static_cast<int64_t>(c.y() + (1 << 20)) << 21) | (c.z() + (1 << 20));
  }
  /// Distance between two segments (sampled closest points: robust, cheap).
  static double distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    double best = 1e9;
    for (int i = 0; i <= 8; ++i) {
      const Vec3 p = a + (b - a) * (i / 8.0);
      const double t =
          std::clamp((p - c).dot(d - c) / std::max((d - c).squaredNorm(), 1e-30), 0.0, 1.0);
      best = std::min(best, (p - c - t * (d - c)).norm());
    }
    return best;
  }
  double cell_;
  std::vector<Seg> segs_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
};

struct Tip {
  int point;    // centreline index of the vessel's end
  Vec3 dir;     // unit direction of the vessel at its end
  Vec3 normal;  // normal of the last bifurcation plane
  double r;     // [m]
  int vessel;   // id of the vessel ending here
  int sibling;  // id of its sibling (-1 for roots)
  int named;    // index of its name in Centerline::vessel_names
};

/// A daughter vessel proposed at a tip: from a through m to b, its end
/// direction and radius [m].
struct Daughter {
  Vec3 a, m, b, dir;
  double r;
};

/// One attempt at a bifurcation at `tip`: two daughters by Murray's law
/// (radii r1^3 + r2^3 = r^3, the ratio and the plane drawn from `uni`),
/// each of 8-16 radii in two segments. False when a daughter leaves the
/// growth box or collides with a vessel other than its parent and sibling.
bool proposeBifurcation(const Tip& tip, const NetworkOptions& options, const Centerline& c,
                        const SegmentHash& hash, Uniform* uni, Daughter kids[2], Vec3* plane) {
  const double gamma = uni->between(0.6, 1.0);  // r2 / r1
  const double r1 = tip.r / std::cbrt(1.0 + gamma * gamma * gamma);
  const double r2 = gamma * r1;
  auto murray = [&](double ra, double rb) {
    const double cosv =
        (std::pow(tip.r, 4) + std::pow(ra, 4) - std::pow(rb, 4)) / (2.0 * tip.r * tip.r * ra * ra);
    return std::acos(std::clamp(cosv, -1.0, 1.0));
  };
  const double turn = (90.0 + uni->between(-30.0, 30.0)) * M_PI / 180.0;
  *plane = Eigen::AngleAxisd(turn, tip.dir) * tip.normal;  // bifurcation plane normal
  const Vec3 side = plane->cross(tip.dir).normalized();
  for (int k = 0; k < 2; ++k) {
    const double r = k == 0 ? r1 : r2;
    const double angle = (k == 0 ? 1.0 : -1.0) * murray(r, k == 0 ? r2 : r1);
    const Vec3 dir = (std::cos(angle) * tip.dir + std::sin(angle) * side).normalized();
    const double len = uni->between(8.0, 16.0) * r;
    const Vec3 a = c.position[tip.point];
    const Vec3 bend = Eigen::AngleAxisd(uni->between(-0.2, 0.2), *plane) * dir;
    const Vec3 m = a + 0.5 * len * dir;
    const Vec3 b = m + 0.5 * len * bend;
    kids[k] = {a, m, b, bend, r};
    if (!options.growth_box.contains(b) || !options.growth_box.contains(m)) return false;
    // Skip the first part near the junction, where the parent and sibling meet.
    const Vec3 start = a + std::min(0.5 * len, 2.5 * tip.r) * dir;
    if (hash.collides(start, m, r, tip.vessel, tip.sibling) ||
        hash.collides(m, b, r, tip.vessel, tip.sibling))
      return false;
  }
  return true;
}

}  // namespace

int growNetwork(const NetworkOptions& options, Centerline* c) {
  Uniform uni(options.seed);
  nameVessels(c);
  SegmentHash hash(4e-3);
  std::vector<int> children(c->numPoints(), 0);
  for (int i = 0; i < c->numPoints(); ++i)
    if (c->parent[i] >= 0) ++children[c->parent[i]];
  // Existing vessels: one id per base segment chain is enough for the checks.
  for (int i = 0; i < c->numPoints(); ++i)
    if (c->parent[i] >= 0)
      hash.add(c->position[c->parent[i]], c->position[i], c->radius[i], -2 - c->type[i]);

  std::deque<Tip> queue;
  int next_vessel = 0;
  for (int i = 0; i < c->numPoints(); ++i) {
    if (children[i] != 0 || c->parent[i] < 0) continue;
    if (options.only_type >= 0 && c->type[i] != options.only_type) continue;
    const Vec3 dir = (c->position[i] - c->position[c->parent[i]]).normalized();
    queue.push_back(
        {i, dir, dir.unitOrthogonal(), c->radius[i], -2 - c->type[i], -1, c->vessel[i]});
  }

  auto addPoint = [&](const Vec3& p, double r, int parent, int named) {
    c->position.push_back(p);
    c->radius.push_back(r);
    c->parent.push_back(parent);
    c->type.push_back(7);
    c->vessel.push_back(named);
    return c->numPoints() - 1;
  };

  int added = 0;
  while (!queue.empty() && added < options.vessels) {
    const Tip tip = queue.front();
    queue.pop_front();
    if (tip.r < options.min_radius * 1.26) continue;  // daughters would be too thin
    Daughter kids[2];
    Vec3 plane;
    int attempt = 0;
    while (attempt < 8 && !proposeBifurcation(tip, options, *c, hash, &uni, kids, &plane))
      ++attempt;
    if (attempt == 8) continue;
    const int ids[2] = {next_vessel, next_vessel + 1};
    next_vessel += 2;
    for (int k = 0; k < 2; ++k) {
      const Daughter& ch = kids[k];
      const int named = static_cast<int>(c->vessel_names.size());
      c->vessel_names.push_back(c->vessel_names[tip.named] + (k == 0 ? "_1" : "_2"));
      const int pm = addPoint(ch.m, ch.r, tip.point, named);
      const int pb = addPoint(ch.b, ch.r, pm, named);
      hash.add(ch.a, ch.m, ch.r, ids[k]);
      hash.add(ch.m, ch.b, ch.r, ids[k]);
      queue.push_back({pb, ch.dir, plane, ch.r, ids[k], ids[1 - k], named});
    }
    added += 2;
  }
  return added;
}

}  // namespace evsim
