// Device pairs (contact/device_pairs.h): the grid searches of point pairs
// and of element pairs against brute-force scans of every pair, on random
// dense clouds and chains of two devices (self-pairs and pairs between
// devices, held points and elements, lumens), also from candidates kept
// from pass to pass or rebuilt with their slack carried over, and across a
// detachment's cut; and the closest points of two
// straight wires crossed at angles from 5 to 90 degrees against the
// analytic distance of their axes; the swept test of a wire carried through
// another in one step against where and when the two first touch.
#include "contact/device_pairs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <tuple>

namespace evsim {
namespace {

using pairs::ElementRef;
using pairs::Pair;
using pairs::PointPair;
using pairs::PointRef;

/// The grid's pairs equal the brute force's, in order, to the last bit;
/// returns how many.
template <typename P>
int expectSamePairs(const std::vector<P>& grid, const std::vector<P>& brute) {
  EXPECT_EQ(grid.size(), brute.size());
  for (size_t k = 0; k < grid.size() && k < brute.size(); ++k) {
    EXPECT_EQ(grid[k].a, brute[k].a);
    EXPECT_EQ(grid[k].b, brute[k].b);
    EXPECT_EQ(grid[k].distance, brute[k].distance);
  }
  return static_cast<int>(grid.size());
}

/// Every pair i < j, kept under the documented rules: one point free, not
/// in the other device's lumen, closer than r_i + r_j + margin and not
/// coincident, on one device more than 2 (r_i + r_j) + 2 element lengths
/// apart along it; per element pair the closest (lowest indices on ties).
std::vector<PointPair> bruteForcePointPairs(const std::vector<DeviceModel>& devices,
                                            const std::vector<PointRef>& pts, double margin) {
  std::map<std::tuple<int, int, int, int>, PointPair> best;
  for (size_t i = 0; i < pts.size(); ++i) {
    for (size_t j = i + 1; j < pts.size(); ++j) {
      const PointRef &a = pts[i], &b = pts[j];
      if (!a.free && !b.free) continue;
      if (a.in_lumen_of == b.device || b.in_lumen_of == a.device) continue;
      const double d = (a.p - b.p).norm();
      if (d == 0.0 || d >= a.r + b.r + margin) continue;
      if (a.device == b.device) {
        const double le = std::max(devices[a.device].elements[a.element].length,
                                   devices[b.device].elements[b.element].length);
        if (std::abs(a.s - b.s) <= 2.0 * (a.r + b.r) + 2.0 * le) continue;
      }
      const auto key = std::make_tuple(a.device, a.element, b.device, b.element);
      const auto it = best.find(key);
      const PointPair p{static_cast<int>(i), static_cast<int>(j),
                        std::sqrt((a.p - b.p).squaredNorm())};
      if (it == best.end() || p.distance < it->second.distance) best[key] = p;
    }
  }
  std::vector<PointPair> out;
  for (const auto& [key, p] : best) out.push_back(p);
  return out;
}

/// Two devices' 300 points each, uniform in the cube of edge `box` [m]
/// around the origin: nine in ten free, radii 0.1-0.15 mm, a fifth of the
/// second device's in the first one's lumen.
std::vector<PointRef> randomCloud(double box, double element_length, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<PointRef> pts;
  for (int device = 0; device < 2; ++device)
    for (int e = 0; e < 300; ++e) {
      const Vec3 p = box * Vec3(u(*rng), u(*rng), u(*rng)) - Vec3::Constant(box / 2);
      pts.push_back({u(*rng) < 0.9, device, e, e, e * element_length, p, 1e-4 + 5e-5 * u(*rng),
                     device == 1 && u(*rng) < 0.2 ? 0 : -1});
    }
  return pts;
}

TEST(DevicePairs, PointGridSearchFindsExactlyTheBruteForcePairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double element_length = 5e-4;  // [m]
  std::vector<DeviceModel> devices(2);
  for (auto& d : devices) d.elements.assign(300, BeamElementRest{element_length});
  int compared = 0, found = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const double box = 2e-3 + 4e-3 * u(rng);  // [m] edge of the cloud (dense to sparse)
    std::vector<PointRef> pts = randomCloud(box, element_length, &rng);
    for (double margin : {0.0, -1e-6, 5e-5}) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " margin " + std::to_string(margin));
      found += expectSamePairs(pairs::findPointPairs(devices, pts, margin),
                               bruteForcePointPairs(devices, pts, margin));
      ++compared;
    }
  }
  EXPECT_EQ(compared, 60);
  EXPECT_GT(found, 1000);  // the clouds are dense enough to test something
  std::printf("[ metric   ] %d point pairs found in 60 clouds, all equal to the brute force\n",
              found);
}

TEST(DevicePairs, PointCandidatesKeptFromPassToPassFindTheBruteForcePairs) {
  // The loop's passes, and the next steps, move the points a little: the
  // candidates built at one pass are reused while every point was there,
  // with its radius, and moved less than the skin, else rebuilt. Either way
  // the pairs equal the brute force's at each pass; a point the build did
  // not see, or one whose radius changed, rebuilds them.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0), jitter(-1.0, 1.0);
  const double element_length = 5e-4;  // [m]
  std::vector<DeviceModel> devices(2);
  for (auto& d : devices) d.elements.assign(300, BeamElementRest{element_length});
  pairs::PointCandidates candidates;
  int found = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const double box = 2e-3 + 2e-3 * u(rng);  // [m]
    std::vector<PointRef> pts = randomCloud(box, element_length, &rng);
    const int builds = candidates.builds, reuses = candidates.reuses;
    // Built here (the last trial's points moved by far more than the skin),
    // then moved by up to 0.3 skins twice (from the build), 5 skins, a
    // point left out of the build and a radius changed.
    for (const std::string what : {"build", "0.3", "0.3", "5", "unseen", "radius"}) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " " + what);
      std::vector<PointRef> at = pts;
      const double moved = what == "0.3" ? 0.3 : what == "5" ? 5.0 : 0.0;
      for (PointRef& q : at)
        q.p +=
            moved * candidates.skin / std::sqrt(3.0) * Vec3(jitter(rng), jitter(rng), jitter(rng));
      if (what == "5") pts = at;  // the next passes from here
      if (what == "unseen")
        at.push_back(
            {true, 0, 300, 299, 300 * element_length, at[7].p, 1e-4, -1});  // on top of point 7
      if (what == "radius") at[3].r *= 1.01;
      for (double margin : {0.0, -1e-6}) {
        const std::vector<PointPair> kept = pairs::findPointPairs(devices, at, margin, &candidates);
        found += expectSamePairs(kept, bruteForcePointPairs(devices, at, margin));
      }
    }
    // Per pass two searches (margins 0 and -1e-6 m, the second always
    // reusing the first's): built at "build", "5", "unseen", "radius".
    EXPECT_EQ(candidates.builds - builds, 4);
    EXPECT_EQ(candidates.reuses - reuses, 8);
  }
  EXPECT_GT(found, 500);
  std::printf(
      "[ metric   ] %d point pairs from kept and rebuilt candidates, all equal to the brute "
      "force\n",
      found);
}

/// A device of `nodes` nodes along a random walk of steps `length` [m]
/// inside the cube of edge `box` around the origin, each node's frame
/// along its chords.
DeviceModel randomChain(int nodes, double length, double box, std::mt19937* rng, DeviceState* x) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  DeviceModel m;
  m.num_nodes = nodes;
  m.elements.assign(nodes - 1, BeamElementRest{length});
  for (int i = 0; i < nodes; ++i) m.node_s.push_back(i * length);
  x->position.assign(1, Vec3(u(*rng), u(*rng), u(*rng)) * box / 2);
  while (static_cast<int>(x->position.size()) < nodes) {
    const Vec3 step = Vec3(u(*rng), u(*rng), u(*rng)).normalized() * length;
    const Vec3 next = x->position.back() + step;
    if (next.cwiseAbs().maxCoeff() < box / 2) x->position.push_back(next);
  }
  for (int i = 0; i < nodes; ++i) {
    const Vec3 t =
        (x->position[std::min(i + 1, nodes - 1)] - x->position[std::max(i - 1, 0)]).normalized();
    x->rotation.push_back(Quat::FromTwoVectors(Vec3::UnitX(), t));
  }
  return m;
}

/// The element of sample point sp (its first) of a device at x, as the
/// pair detection describes it: its axis, box and bow at x.
ElementRef elementRef(const DeviceModel& m, const DeviceState& x, int device, const SamplePoint& sp,
                      bool free = true, int in_lumen_of = -1) {
  const int e = sp.element;
  ElementRef el{free, device, e, 0, in_lumen_of, e, sp, pairs::axisBox(m, x, e)};
  el.box.min().array() -= sp.radius;
  el.box.max().array() += sp.radius;
  el.axis = HermiteAxis::of(m, x, e);
  el.bow = el.axis.bow();
  return el;
}

/// Two random chains of 150 nodes in a 3 mm cube, each element with a
/// radius of 100-150 um (the kept candidates' tests).
struct TwoChains {
  std::vector<DeviceModel> devices;
  std::vector<DeviceState> x{2};
  std::vector<SamplePoint> points;  // per element of both chains, in order

  explicit TwoChains(std::mt19937* rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int device = 0; device < 2; ++device) {
      devices.push_back(randomChain(150, 5e-4, 3e-3, rng, &x[device]));
      for (int e = 0; e + 1 < 150; ++e) points.push_back({e, 0.0, 1e-4 + 5e-5 * u(*rng), 0.0});
    }
  }
  /// Their elements at `at`, the first `held` of each chain held (as in an
  /// introducer).
  std::vector<ElementRef> elementsAt(const std::vector<DeviceState>& at, int held) const {
    std::vector<ElementRef> els;
    for (int device = 0; device < 2; ++device)
      for (int e = 0; e + 1 < 150; ++e)
        els.push_back(
            elementRef(devices[device], at[device], device, points[149 * device + e], e >= held));
    return els;
  }
};

/// Every pair of elements i < j under the documented rules (one free, not
/// in the other device's lumen, the axes closer than r_i + r_j + margin,
/// on one device more than 2 (r_i + r_j) + 2 element lengths apart along
/// it at the closest points, a closest point at a distal node left to the
/// next element), in index order.
std::vector<Pair> bruteForcePairs(const std::vector<DeviceModel>& devices,
                                  const std::vector<DeviceState>& x,
                                  const std::vector<ElementRef>& els, double margin) {
  std::vector<Pair> out;
  for (size_t i = 0; i < els.size(); ++i)
    for (size_t j = i + 1; j < els.size(); ++j) {
      const ElementRef &a = els[i], &b = els[j];
      if (!a.free && !b.free) continue;
      if (a.in_lumen_of == b.device || b.in_lumen_of == a.device) continue;
      const DeviceModel &ma = devices[a.device], &mb = devices[b.device];
      double xa = 0.0, xb = 0.0;
      const double d = pairs::closestAxisPoints(ma, x[a.device], a.element, mb, x[b.device],
                                                b.element, &xa, &xb);
      const double ra = a.point.radius, rb = b.point.radius;
      if (!(d < ra + rb + margin)) continue;
      if (a.device == b.device && a.body == b.body) {
        const double le = std::max(ma.elements[a.element].length, mb.elements[b.element].length);
        const double sa = ma.node_s[a.element] + xa * le, sb = mb.node_s[b.element] + xb * le;
        if (std::abs(sa - sb) <= 2.0 * (ra + rb) + 2.0 * le) continue;
      }
      if ((xa == 1.0 && a.element + 2 < ma.num_nodes) ||
          (xb == 1.0 && b.element + 2 < mb.num_nodes))
        continue;
      Pair p{static_cast<int>(i), static_cast<int>(j), a.point, b.point,
             Vec3::Zero(),        Vec3::Zero(),        d};
      p.on_a.xi = xa;
      p.on_b.xi = xb;
      out.push_back(p);
    }
  return out;
}

/// The distance between two axes by brute force: the least over a
/// 401 x 401 grid of their parameters, then over a 201 x 201 grid a grid
/// step wide around it (within about 1e-12 m for these elements).
double bruteForceAxisDistance(const HermiteAxis& a, const HermiteAxis& b) {
  constexpr int kSteps = 400, kFine = 200;
  double best = std::numeric_limits<double>::infinity(), at_a = 0.0, at_b = 0.0;
  auto search = [&](double a0, double b0, double width, int steps) {
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; j <= steps; ++j) {
        const double xa = std::clamp(a0 + width * i / steps, 0.0, 1.0);
        const double xb = std::clamp(b0 + width * j / steps, 0.0, 1.0);
        const double d = (a.at(xa).position - b.at(xb).position).norm();
        if (d < best) best = d, at_a = xa, at_b = xb;
      }
  };
  search(0.0, 0.0, 1.0, kSteps);
  const double h = 1.0 / kSteps;
  search(at_a - h, at_b - h, 2.0 * h, kFine);
  return best;
}

/// A helix of radius R [m] and rise c [m per rad] about z: the element
/// between angles t0 and t1 as a Hermite axis (tangents times its length).
HermiteAxis helixElement(double R, double c, double t0, double t1) {
  auto point = [&](double t) { return Vec3(R * std::cos(t), R * std::sin(t), c * t); };
  auto unitTangent = [&](double t) {
    return Vec3(-R * std::sin(t), R * std::cos(t), c).normalized();
  };
  const double length = std::hypot(R, c) * (t1 - t0);
  return {point(t0), point(t1), length * unitTangent(t0), length * unitTangent(t1)};
}

TEST(DevicePairs, AxisGapBoundNeverExceedsTheAxesDistanceAndIsTightForTurnsSideBySide) {
  // Random curved elements (0.5 mm, tangents up to 60 degrees off their
  // chords) anywhere within 1 mm of each other: the bound is a lower bound.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tighter = 0;
  double worst_excess = -1.0;
  for (int trial = 0; trial < 150; ++trial) {
    auto randomAxis = [&](const Vec3& centre) {
      const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized() * 5e-4;
      const Vec3 p0 = centre - d / 2, p1 = centre + d / 2;
      auto tilt = [&] { return (d + 0.5 * d.norm() * Vec3(u(rng), u(rng), u(rng))).normalized(); };
      return HermiteAxis{p0, p1, d.norm() * tilt(), d.norm() * tilt()};
    };
    const HermiteAxis a = randomAxis(Vec3::Zero());
    const HermiteAxis b = randomAxis(5e-4 * Vec3(u(rng), u(rng), u(rng)));
    const double bound = pairs::axisGapBound(a, a.bow(), b, b.bow());
    const double distance = bruteForceAxisDistance(a, b);
    worst_excess = std::max(worst_excess, bound - distance);
    EXPECT_LE(bound, distance + 1e-15) << "trial " << trial;  // (exact where the ends are closest)
    double s = 0.0, t = 0.0;
    const double chords =
        pairs::closestAxisPoints(HermiteAxis{a.p0, a.p1, a.p1 - a.p0, a.p1 - a.p0},
                                 HermiteAxis{b.p0, b.p1, b.p1 - b.p0, b.p1 - b.p0}, &s, &t);
    tighter += bound > chords - a.bow() - b.bow() + 1e-9;
  }
  EXPECT_GT(tighter, 15);  // the separating axis does better than the bows often
  // A packed coil's turns side by side: elements of 0.48 mm on a helix of
  // 1 mm radius rising 0.253 mm a turn (a 0.25 mm coil's turns 3 um
  // apart), against the next turn's. The bows (about 34 um each) rule out
  // no such pair at a reach of 0.25 mm; the bound is within a micrometre
  // of the distance and does.
  constexpr double kPi = 3.14159265358979323846;
  const double R = 1e-3, rise = 2.53e-4 / (2.0 * kPi), dt = 0.48e-3 / R;
  for (double t0 : {0.0, 0.7, 2.1}) {
    for (double shift : {0.0, 0.2, 0.5}) {  // the upper element shifted along the turn
      const double t1 = t0 + 2.0 * kPi + shift * dt;
      const HermiteAxis lower = helixElement(R, rise, t0, t0 + dt);
      const HermiteAxis upper = helixElement(R, rise, t1, t1 + dt);
      const double distance = bruteForceAxisDistance(lower, upper);
      const double bound = pairs::axisGapBound(lower, lower.bow(), upper, upper.bow());
      EXPECT_NEAR(distance, 2.53e-4, 2e-6);
      EXPECT_LE(bound, distance);
      EXPECT_GT(bound, distance - 1e-6);
      EXPECT_GT(upper.bow() + lower.bow(), 6e-5);  // what the bows alone leave: 0.19 mm
    }
  }
  std::printf(
      "[ metric   ] axisGapBound: %d of 150 random pairs tighter than the bows; worst "
      "bound - distance %.3g m (<= 0)\n",
      tighter, worst_excess);
}

TEST(DevicePairs, GridSearchFindsExactlyTheBruteForcePairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int compared = 0, found = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const double box = 2e-3 + 4e-3 * u(rng);  // [m] edge of the cube (dense to sparse)
    std::vector<DeviceModel> devices;
    std::vector<DeviceState> x(2);
    std::vector<ElementRef> els;
    for (int device = 0; device < 2; ++device) {
      devices.push_back(randomChain(150, 5e-4, box, &rng, &x[device]));
      for (int e = 0; e + 1 < 150; ++e) {
        const SamplePoint sp{e, 0.0, 1e-4 + 5e-5 * u(rng), 0.0};
        const bool free = u(rng) < 0.9;
        const int in_lumen_of = device == 1 && u(rng) < 0.2 ? 0 : -1;
        els.push_back(elementRef(devices.back(), x[device], device, sp, free, in_lumen_of));
      }
    }
    for (double margin : {0.0, -1e-6, 5e-5}) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " margin " + std::to_string(margin));
      found += expectSamePairs(pairs::findPairs(devices, x, els, margin),
                               bruteForcePairs(devices, x, els, margin));
      ++compared;
    }
  }
  EXPECT_EQ(compared, 36);
  EXPECT_GT(found, 1000);  // the chains are dense enough to test something
  std::printf("[ metric   ] %d element pairs found in 36 chains, all equal to the brute force\n",
              found);
}

TEST(DevicePairs, CandidatesKeptFromPassToPassFindTheBruteForcePairs) {
  // The activation loop's passes, and the steps, move the elements a
  // little: the candidates built at one pass (boxes grown by a skin) are
  // reused while every element is free or held as there and its box stays
  // within its grown box, else rebuilt. Either way the pairs equal the
  // brute force's at each pass.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  int found = 0;
  pairs::PairCandidates candidates;
  for (int trial = 0; trial < 8; ++trial) {
    const TwoChains chains(&rng);
    const std::vector<DeviceModel>& devices = chains.devices;
    const std::vector<DeviceState>& x = chains.x;
    candidates.reach = -1.0;  // a new step
    const int builds = candidates.builds, reuses = candidates.reuses;
    // Built here, then nodes moved by up to 0.2 and 5 skins; then, where
    // they are, the held elements set free (pairs of two held elements are
    // no candidates: the list must be rebuilt).
    std::vector<DeviceState> at = x;
    for (double moved : {0.0, 0.2, 5.0, -1.0}) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " moved " + std::to_string(moved));
      if (moved >= 0.0) {
        at = x;
        for (DeviceState& state : at)
          for (Vec3& p : state.position)
            p += moved * candidates.skin / std::sqrt(3.0) *
                 Vec3(jitter(rng), jitter(rng), jitter(rng));
      }
      const std::vector<ElementRef> els = chains.elementsAt(at, moved >= 0.0 ? 20 : 0);
      found += expectSamePairs(pairs::findPairs(devices, at, els, 0.0, nullptr, true, &candidates),
                               bruteForcePairs(devices, at, els, 0.0));
    }
    EXPECT_EQ(candidates.builds - builds, 3);  // here, after 5 skins, once the held ones are free
    EXPECT_EQ(candidates.reuses - reuses, 1);  // after 0.2 skins
  }
  EXPECT_GT(found, 500);
  std::printf(
      "[ metric   ] %d element pairs from kept and rebuilt candidates, all equal to the "
      "brute force\n",
      found);
}

/// A pass of a walk of both chains: every node of `at` moved by `shift`
/// [m] and up to `jitter` skins more, then the candidates' pairs at
/// `margin` checked against the brute force's. Returns how many.
int walkedPass(const TwoChains& chains, const Vec3& shift, double jitter, double margin,
               std::vector<DeviceState>* at, pairs::PairCandidates* candidates, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double reach = jitter * candidates->skin / std::sqrt(3.0);
  for (DeviceState& state : *at)
    for (Vec3& p : state.position) p += shift + reach * Vec3(u(*rng), u(*rng), u(*rng));
  const std::vector<ElementRef> els = chains.elementsAt(*at, 20);
  return expectSamePairs(
      pairs::findPairs(chains.devices, *at, els, margin, nullptr, true, candidates),
      bruteForcePairs(chains.devices, *at, els, margin));
}

TEST(DevicePairs, CandidatesKeptApartByTheirSlackFindTheBruteForcePairs) {
  // The passes of a step and the steps after it move the elements a little
  // at a time, within the skin: the list is reused, and a candidate whose
  // last measured gap, less how far both axes moved since the list was
  // built, still keeps it apart is skipped. The pairs equal the brute
  // force's at every pass and margin, and most candidates are skipped.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  int found = 0, passes = 0;
  long kept_apart = 0, checked = 0;
  for (int trial = 0; trial < 6; ++trial) {
    pairs::PairCandidates candidates;
    const TwoChains chains(&rng);
    const std::vector<DeviceModel>& devices = chains.devices;
    // Built at x with the largest margin, then 12 passes, each moving every
    // node by up to a twentieth of the skin from the last (a random walk
    // that stays within the skin), at margins 5e-5, 0 and -1e-6 in turn.
    std::vector<DeviceState> at = chains.x;
    pairs::findPairs(devices, at, chains.elementsAt(at, 20), 5e-5, nullptr, true, &candidates);
    const long before = candidates.kept_apart;
    for (int pass = 0; pass < 12; ++pass) {
      const double margin = pass % 3 == 0 ? 5e-5 : pass % 3 == 1 ? 0.0 : -1e-6;
      SCOPED_TRACE("trial " + std::to_string(trial) + " pass " + std::to_string(pass));
      found += walkedPass(chains, Vec3::Zero(), 0.05, margin, &at, &candidates, &rng);
      checked += static_cast<long>(candidates.pairs.size());
      ++passes;
    }
    EXPECT_EQ(candidates.builds, 1);  // reused at every pass
    kept_apart += candidates.kept_apart - before;
  }
  EXPECT_EQ(passes, 72);
  EXPECT_GT(found, 500);
  EXPECT_GT(kept_apart, checked / 4);  // the bound spares a good part of the checks
  std::printf(
      "[ metric   ] %d element pairs over 72 passes of a kept list, all equal to the brute "
      "force; %ld of %ld candidates skipped on their slack\n",
      found, kept_apart, checked);
}

TEST(DevicePairs, RebuiltCandidatesCarryTheSlackOverAndFindTheBruteForcePairs) {
  // Steps of a packed coil, whose turns move together: every pass shifts
  // all nodes by 0.6 skins (one direction per trial) and each node by
  // up to 0.1 skins more, so the list is rebuilt every pass or two; each
  // build carries the slack of the list it replaces over to the pairs in
  // both, less how far their axes moved relative to each other. The pairs
  // equal the brute force's at every pass, and the carried slack spares
  // most of the builds' checks. Then, where the elements stand,
  // each chain is cut in two bodies (a detachment): the pairs across the
  // cut, neighbours before, are checked, kept list or not.
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  int found = 0, across = 0;
  long carried = 0, built = 0;
  for (int trial = 0; trial < 6; ++trial) {
    pairs::PairCandidates candidates;
    const TwoChains chains(&rng);
    const std::vector<DeviceModel>& devices = chains.devices;
    std::vector<DeviceState> at = chains.x;
    pairs::findPairs(devices, at, chains.elementsAt(at, 20), 0.0, nullptr, true, &candidates);
    const int builds = candidates.builds;
    const Vec3 direction = Vec3(jitter(rng), jitter(rng), jitter(rng)).normalized();
    for (int pass = 0; pass < 12; ++pass) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " pass " + std::to_string(pass));
      const long candidates_before = static_cast<long>(candidates.pairs.size());
      const int builds_before = candidates.builds;
      found +=
          walkedPass(chains, 0.6 * candidates.skin * direction, 0.1, 0.0, &at, &candidates, &rng);
      if (candidates.builds > builds_before) built += candidates_before;
    }
    EXPECT_GE(candidates.builds - builds, 4);  // rebuilt at a third of the passes at least
    carried += candidates.carried;
    // The cut: elements 75 on of each chain a second body, nothing moved.
    std::vector<ElementRef> els = chains.elementsAt(at, 20);
    for (ElementRef& el : els) el.body = el.element >= 75 ? 1 : 0;
    const std::vector<Pair> cut =
        pairs::findPairs(devices, at, els, 0.0, nullptr, true, &candidates);
    found += expectSamePairs(cut, bruteForcePairs(devices, at, els, 0.0));
    for (const Pair& p : cut)
      across += els[p.a].device == els[p.b].device && els[p.a].body != els[p.b].body;
  }
  EXPECT_GT(found, 500);
  EXPECT_GT(carried, built / 2);  // most candidates of a build keep their slack
  EXPECT_GT(across, 0);           // the cut made pairs that were neighbours before
  std::printf(
      "[ metric   ] %d element pairs over 78 passes of rebuilt lists, all equal to the brute "
      "force; %ld candidates of the builds kept apart by carried slack (the lists replaced "
      "held %ld); %d pairs across a cut\n",
      found, carried, built, across);
}

/// A straight element from a to b (its frames along it).
DeviceModel straightElement(const Vec3& a, const Vec3& b, DeviceState* x) {
  DeviceModel m;
  m.num_nodes = 2;
  m.elements.assign(1, BeamElementRest{(b - a).norm()});
  m.node_s = {0.0, (b - a).norm()};
  x->position = {a, b};
  const Quat q = Quat::FromTwoVectors(Vec3::UnitX(), b - a);
  x->rotation = {q, q};
  return m;
}

/// The direction between the closest points of the stretches pa + s ta
/// (|s| <= ra) and pb + t tb (|t| <= rb), by brute force: the least distance
/// over a 401 x 401 grid of (s, t), then a 401 x 401 grid of two cells
/// around it, and so on five times.
Vec3 bruteForceStretchNormal(const Vec3& pa, const Vec3& ta, double ra, const Vec3& pb,
                             const Vec3& tb, double rb, double* distance) {
  double s0 = -ra, s1 = ra, t0 = -rb, t1 = rb, best_s = 0.0, best_t = 0.0;
  for (int level = 0; level < 5; ++level) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 400; ++i)
      for (int j = 0; j <= 400; ++j) {
        const double s = s0 + (s1 - s0) * i / 400.0, t = t0 + (t1 - t0) * j / 400.0;
        const double dist = (pa + s * ta - pb - t * tb).squaredNorm();
        if (dist < best) best = dist, best_s = s, best_t = t;
      }
    const double ds = (s1 - s0) / 200.0, dt = (t1 - t0) / 200.0;
    s0 = std::max(-ra, best_s - ds), s1 = std::min(ra, best_s + ds);
    t0 = std::max(-rb, best_t - dt), t1 = std::min(rb, best_t + dt);
  }
  const Vec3 w = pa + best_s * ta - pb - best_t * tb;
  *distance = w.norm();
  return w.normalized();
}

TEST(DevicePairs, APointPairsNormalJoinsTheClosestPointsOfTheStretchesItsPointsStandFor) {
  // 200 random point pairs within 0.5 mm, tangents at random angles, each
  // point standing for 0.1-0.3 mm of its axis either side: the normal is the
  // direction between the two stretches' closest points (brute force), from
  // b to a.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), reach(1e-4, 3e-4);
  double worst = 0.0;
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 pa = 5e-4 * Vec3(u(rng), u(rng), u(rng)), pb = 5e-4 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 ta = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 tb = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double ra = reach(rng), rb = reach(rng);
    double distance = 0.0;
    const Vec3 expected = bruteForceStretchNormal(pa, ta, ra, pb, tb, rb, &distance);
    if (distance < 1e-5) continue;  // (the stretches meet: their normal is the fallback's)
    const Vec3 n = pairs::pairNormal(pa, ta, pb, tb, ra, rb);
    worst = std::max(worst, (n - expected).norm());
    ++checked;
  }
  std::printf("[ metric   ] %d pairs: normal within %.3e of the brute force's\n", checked, worst);
  EXPECT_GT(checked, 150);
  EXPECT_LT(worst, 1e-6);
}

TEST(DevicePairs, TurnsSideBySideInAPlanePushApartInThatPlane) {
  // Two concentric turns of a 0.25 mm coil in the x-y plane (radii 2.0 and
  // 2.25 mm: side by side, touching), sampled every 0.5 mm with the outer
  // turn's samples shifted by 0-0.25 mm along it: every pair of facing
  // samples is pushed apart radially, in the turns' plane (the true normal
  // of two touching tori). Crossed-cylinder normals (t_a x t_b) there point
  // out of the plane, and their sign flips from pair to pair.
  const double inner = 2.0e-3, outer = 2.25e-3, spacing = 5e-4, reach = 0.5 * spacing;
  double worst = 0.0;
  int checked = 0;
  for (double shift : {0.0, 0.05e-3, 0.12e-3, 0.2e-3, 0.25e-3})
    for (int k = 0; k < 24; ++k) {
      const double phi_a = k * spacing / outer + shift / outer;
      const double phi_b = std::round(phi_a * inner / spacing) * spacing / inner;  // facing sample
      const Vec3 pa = outer * Vec3(std::cos(phi_a), std::sin(phi_a), 0.0);
      const Vec3 ta(-std::sin(phi_a), std::cos(phi_a), 0.0);
      const Vec3 pb = inner * Vec3(std::cos(phi_b), std::sin(phi_b), 0.0);
      const Vec3 tb(-std::sin(phi_b), std::cos(phi_b), 0.0);
      const Vec3 n = pairs::pairNormal(pa, ta, pb, tb, reach, reach);
      const double phi = 0.5 * (phi_a + phi_b);
      const Vec3 radial(std::cos(phi), std::sin(phi), 0.0);
      worst = std::max(worst, std::abs(n.z()));
      EXPECT_GT(n.dot(radial), 0.99) << "shift " << shift << " sample " << k;
      ++checked;
    }
  std::printf("[ metric   ] %d facing pairs of touching turns: out of plane at most %.3e\n",
              checked, worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(DevicePairs, CrossedWiresTouchWhereTheirAxesAreClosest) {
  // Wire a along x (10 mm, centred at an offset u along it), wire b at an
  // angle theta to it in the x-y plane, lifted by h along z and centred at
  // an offset v along itself: the axes' closest points are a's point at x =
  // 0 and b's at its centre less v, h apart, wherever the offsets put them
  // on the elements (between samples or not). The pair: found, with that
  // distance and those points, to 1e-12 m.
  int checked = 0;
  const double ra = 1.25e-4, rb = 1.25e-4, h = 2.3e-4;  // [m] the wires overlap by 20 um
  for (double degrees = 5.0; degrees <= 90.0; degrees += 5.0) {
    const double theta = degrees * M_PI / 180.0;
    const Vec3 tb(std::cos(theta), std::sin(theta), 0.0);
    for (double u : {-4e-3, -1.3e-3, 0.0, 2.1e-3})
      for (double v : {-3.7e-3, -0.4e-3, 0.0, 4.2e-3}) {
        std::vector<DeviceState> x(2);
        std::vector<DeviceModel> devices;
        devices.push_back(straightElement(Vec3(-5e-3 - u, 0, 0), Vec3(5e-3 - u, 0, 0), &x[0]));
        const Vec3 cb = Vec3(0, 0, h) - v * tb;
        devices.push_back(straightElement(cb - 5e-3 * tb, cb + 5e-3 * tb, &x[1]));
        std::vector<ElementRef> els;
        for (int d = 0; d < 2; ++d) {
          els.push_back(elementRef(devices[d], x[d], d, {0, 0.0, d == 0 ? ra : rb, 0.0}));
        }
        const std::vector<Pair> found = pairs::findPairs(devices, x, els, 0.0);
        ASSERT_EQ(found.size(), 1u) << degrees << " deg, u " << u << ", v " << v;
        const Pair& p = found[0];
        EXPECT_NEAR(p.distance - (ra + rb), h - (ra + rb), 1e-12);
        EXPECT_NEAR((p.pa - Vec3::Zero()).norm(), 0.0, 1e-12);
        EXPECT_NEAR((p.pb - Vec3(0, 0, h)).norm(), 0.0, 1e-12);
        ++checked;
      }
  }
  EXPECT_EQ(checked, 18 * 16);
}

TEST(DevicePairs, AWireCarriedThroughAnotherInOneStepIsHeldWhereTheyFirstTouched) {
  // Wire b lies along x at z = 0; wire a crosses it at an angle theta in a
  // plane z = const and is carried in one step from z0 = 0.3 mm above it to
  // z1 below it (1 to 10 mm: 1 to 10 m/s at 1 ms), sliding by w along b as
  // it goes. At both ends of the step the axes are apart (no
  // pair without the swept test). Their closest points lie on the common
  // normal z whatever a's lateral shift, so the first touch is where a's
  // axis is r_a + r_b above b's: at s = (z0 - r) / (z0 - z1) of the step,
  // the normal +z (from b toward a); the contact holds the touching points,
  // now (pa - pb) . z = z1 apart along it.
  const double ra = 1.25e-4, rb = 1.25e-4, r = ra + rb, z0 = 3e-4;
  int checked = 0;
  for (double degrees : {5.0, 30.0, 60.0, 90.0}) {
    const double theta = degrees * M_PI / 180.0;
    const Vec3 ta(std::cos(theta), std::sin(theta), 0.0);
    for (double z1 : {-1e-3, -4e-3, -1e-2})
      for (double w : {0.0, 7e-4, -2.2e-3}) {
        std::vector<DeviceModel> devices;
        std::vector<DeviceState> x(2), from(2);
        devices.push_back(
            straightElement(Vec3(w, 0, z1) - 5e-3 * ta, Vec3(w, 0, z1) + 5e-3 * ta, &x[0]));
        straightElement(Vec3(0, 0, z0) - 5e-3 * ta, Vec3(0, 0, z0) + 5e-3 * ta, &from[0]);
        devices.push_back(straightElement(Vec3(-5e-3, 0, 0), Vec3(5e-3, 0, 0), &x[1]));
        from[1] = x[1];
        std::vector<ElementRef> els;
        for (int d = 0; d < 2; ++d)
          els.push_back(elementRef(devices[d], x[d], d, {0, 0.0, d == 0 ? ra : rb, 0.0}));
        EXPECT_TRUE(pairs::findPairs(devices, x, els, 0.0).empty());  // apart at x
        // The step's motion: each element's box and sweep as the pair
        // detection gives them (a moved by |(w, 0, z1 - z0)|, b not at all).
        const pairs::StartAxes start(devices, from);
        const Vec3 shift(w, 0.0, z1 - z0);
        els[0].box.extend(els[0].box.min() - shift);
        els[0].box.extend(els[0].box.max() - shift);
        els[0].sweep = shift.norm();
        els[0].shift = shift;  // (spread 0: every point of a moved by the same shift)
        const std::vector<Pair> found = pairs::findPairs(devices, x, els, 0.0, &start);
        const std::string where =
            std::to_string(degrees) + " deg, z1 " + std::to_string(z1) + ", w " + std::to_string(w);
        ASSERT_EQ(found.size(), 1u) << where;
        const Pair& p = found[0];
        EXPECT_TRUE(p.swept) << where;
        EXPECT_NEAR((p.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12) << where;
        EXPECT_NEAR(p.distance, z1, 1e-12) << where;
        EXPECT_NEAR((p.pa - p.pb).dot(Vec3::UnitZ()), z1, 1e-12) << where;
        const pairs::Touch t = pairs::firstTouch(
            start.axis(0, 0), HermiteAxis::of(devices[0], x[0], 0), start.axis(1, 0),
            HermiteAxis::of(devices[1], x[1], 0), r, shift.norm());
        ASSERT_TRUE(t.touched) << where;
        // The advancement's steps (d - r) / speed are exact for a motion
        // straight along the normal; sideways, it takes a few, stopping
        // within 1 % of r of the touch.
        const double s_touch = (z0 - r) / (z0 - z1);
        EXPECT_LE(t.s, s_touch + 1e-12) << where;
        EXPECT_GE(t.s, (z0 - 1.01 * r) / (z0 - z1) - 1e-12) << where;
        if (w == 0.0) {
          EXPECT_NEAR(t.s, s_touch, 1e-12) << where;
        }
        ++checked;
      }
  }
  EXPECT_EQ(checked, 36);
}

}  // namespace
}  // namespace evsim
