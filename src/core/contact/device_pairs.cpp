// Pairs of device elements whose axes come closer than the sum of their radii
// (the effect 'device_contact'; internal to the contact solver,
// contact_solver.cpp). Declared and documented in device_pairs.h.
#include "device_pairs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace evsim {
namespace pairs {

/// Normal of a contact between two device points, from b to a: each point
/// stands for its axis's stretch pa + s ta, |s| <= reach_a (and b's), and
/// the normal is the direction between those two segments' closest points
/// (Ericson, Real-Time Collision Detection, 5.1.9). Turns crossing within
/// the stretches meet along t_a x t_b, turns side by side across both,
/// whatever offset along them their samples have; never along an axis, as
/// point-to-point normals are (a pair of spheres, which roll off each
/// other). Where the segments meet (reaches 0, or axes through each
/// other), across both axes (crossed cylinders: t_a x t_b), or, for nearly
/// parallel axes, the part of p_a - p_b across t_a.
Vec3 pairNormal(const Vec3& pa, const Vec3& ta, const Vec3& pb, const Vec3& tb, double reach_a,
                double reach_b) {
  const Vec3 d = pa - pb;
  if (reach_a > 0.0 || reach_b > 0.0) {
    const double a = ta.squaredNorm(), e = tb.squaredNorm(), b = ta.dot(tb);
    const double c = ta.dot(d), f = tb.dot(d);
    const double denom = a * e - b * b;
    // s on a's stretch, t on b's: |d + s ta - t tb| least.
    double s = denom > 1e-12 * a * e ? std::clamp((b * f - c * e) / denom, -reach_a, reach_a) : 0.0;
    double t = (b * s + f) / e;
    if (t < -reach_b || t > reach_b) {
      t = std::clamp(t, -reach_b, reach_b);
      s = std::clamp((b * t - c) / a, -reach_a, reach_a);
    }
    const Vec3 w = d + s * ta - t * tb;
    if (w.norm() > 1e-9 * (reach_a + reach_b)) return w.normalized();
  }
  const Vec3 cross = ta.cross(tb);
  if (cross.norm() > 0.1) {
    const Vec3 n = cross.normalized();
    return n.dot(d) >= 0.0 ? n : Vec3(-n);
  }
  const Vec3 across = d - d.dot(ta) * ta;
  return across.norm() > 0.0 ? Vec3(across.normalized()) : d.normalized();
}

namespace {

constexpr int64_t kLow21 = (int64_t{1} << 21) - 1;

/// Points sorted by grid cell, key (z, y, x) with x least significant:
/// row by row ((z, y) fixed), each row in x order, and an open-addressing
/// hash from a row's key to its range.
struct CellRows {
  struct Row {
    int64_t key{-1};  // (z, y)
    int begin{0}, end{0};
  };
  std::vector<std::pair<int64_t, int>> sorted;  // (cell key, point)
  std::vector<Row> table;                       // the hash
  std::vector<Row> rows;                        // the rows in sorted order
  int bits{4};

  CellRows(const std::vector<Vec3>& pts, double cell) {
    auto cellOf = [cell](double v) {
      return static_cast<int64_t>(std::floor(v / cell)) + (1 << 20);
    };
    const int n = static_cast<int>(pts.size());
    sorted.resize(n);
    for (int i = 0; i < n; ++i)
      sorted[i] = {cellOf(pts[i].z()) << 42 | cellOf(pts[i].y()) << 21 | cellOf(pts[i].x()), i};
    std::sort(sorted.begin(), sorted.end());
    while ((1 << bits) < 2 * n) ++bits;
    table.resize(size_t{1} << bits);
    for (int k = 0; k < n;) {
      const int64_t row_key = sorted[k].first >> 21;
      int e = k;
      while (e < n && (sorted[e].first >> 21) == row_key) ++e;
      table[slot(row_key)] = {row_key, k, e};
      rows.push_back({row_key, k, e});
      k = e;
    }
  }
  size_t slot(int64_t row_key) const {
    const uint64_t mask = (uint64_t{1} << bits) - 1;
    uint64_t h = (static_cast<uint64_t>(row_key) * 0x9E3779B97F4A7C15ull) >> (64 - bits);
    while (table[h].key != -1 && table[h].key != row_key) h = (h + 1) & mask;
    return h;
  }
  /// The row (z, y), or one with key -1.
  const Row& row(int64_t z, int64_t y) const { return table[slot(z << 21 | y)]; }
  int64_t x(int k) const { return sorted[k].first & kLow21; }
  /// Calls fn(at, k) for every pair of points (sorted indices) in the same
  /// or neighbouring cells, once. Each pair of cells is visited once, row
  /// against row (both in x order, so a window x - 1 ... x + 1 slides along
  /// the other row): a row with itself (a point against the later points
  /// of its cell and of x + 1), and with the rows (z, y + 1) and (z + 1,
  /// y - 1 ... y + 1), looked up once a row, not once a point.
  template <typename F>
  void forNeighbours(F&& fn) const {
    constexpr int64_t kRowStep[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    for (const Row& r : rows) {
      for (int at = r.begin; at < r.end; ++at)
        for (int k = at + 1; k < r.end && x(k) <= x(at) + 1; ++k) fn(at, k);
      const int64_t y = r.key & kLow21, z = r.key >> 21;
      for (const auto& step : kRowStep) {
        const Row& other = row(z + step[0], y + step[1]);
        if (other.key == -1) continue;
        int first = other.begin;  // the first point of the other row at x - 1 or beyond
        for (int at = r.begin; at < r.end; ++at) {
          const int64_t x0 = x(at);
          while (first < other.end && x(first) < x0 - 1) ++first;
          for (int k = first; k < other.end && x(k) <= x0 + 1; ++k) fn(at, k);
        }
      }
    }
  }
};

/// A pair of points within reach, with its pair of elements.
struct Candidate {
  int64_t elements;  // (device a, element a, device b, element b) packed
  double distance;
  int a, b;
};

/// Per pair of elements the closest candidate (the first index pair on
/// ties, as a scan in index order would keep).
std::vector<PointPair> closestPerElementPair(std::vector<Candidate> found) {
  std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) {
    if (x.elements != y.elements) return x.elements < y.elements;
    if (x.distance != y.distance) return x.distance < y.distance;
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  std::vector<PointPair> out;
  for (size_t k = 0; k < found.size(); ++k)
    if (k == 0 || found[k].elements != found[k - 1].elements)
      out.push_back({found[k].a, found[k].b, found[k].distance});
  return out;
}

/// The Bezier control points of an axis: p0, p0 + m0 / 3, p1 - m1 / 3, p1.
std::array<Vec3, 4> controlPoints(const HermiteAxis& a) {
  return {a.p0, a.p0 + a.m0 / 3.0, a.p1 - a.m1 / 3.0, a.p1};
}

/// Material coordinate of a point of an element [m].
double along(const DeviceModel& m, int e, double xi) {
  return m.node_s[e] + xi * m.elements[e].length;
}

/// Whether the element after e on its body holds e's distal node as its own
/// proximal one (a closest point there is that element's, not e's).
bool nextHoldsEnd(const DeviceModel& m, const DeviceState& x, int e) {
  return e + 1 < m.num_nodes - 1 && e + 1 != x.cut_element;
}

/// How an axis moved between two passes, from its Bezier control points
/// then and now: each axis point moved by the Bezier combination of the
/// control points' displacements, so by their mean `shift` give or take
/// `spread`, and by no more than the largest of them, `drift` [m].
PairCandidates::Motion motionOf(const std::array<Vec3, 4>& then, const std::array<Vec3, 4>& now) {
  std::array<Vec3, 4> moved;
  PairCandidates::Motion m{Vec3::Zero(), 0.0, 0.0};
  for (int q = 0; q < 4; ++q) {
    moved[q] = now[q] - then[q];
    m.shift += 0.25 * moved[q];
    m.drift = std::max(m.drift, moved[q].norm());
  }
  for (int q = 0; q < 4; ++q) m.spread = std::max(m.spread, (moved[q] - m.shift).norm());
  return m;
}

/// A bound [m] of how far any point of one axis moved relative to any point
/// of another, and so of how much their distance shrank: the sum of both
/// drifts, or, where less, their shifts' difference and both spreads (the
/// turns of a packed coil move together, each a few tens of micrometres a
/// step, and their distances change by micrometres).
double relativeMotion(double drift_a, double drift_b, double shift_gap, double spread_a,
                      double spread_b) {
  return std::min(drift_a + drift_b, shift_gap + spread_a + spread_b);
}
double relativeMotion(const PairCandidates::Motion& a, const PairCandidates::Motion& b) {
  return relativeMotion(a.drift, b.drift, (a.shift - b.shift).norm(), a.spread, b.spread);
}

/// The lower bounds of the axes' distances (PairCandidates::slack) of the
/// list a build replaces, to be carried over to the new list: per element of
/// the old list its candidates, by the other's old index, with their slack,
/// and where its axis was when they were measured. A build happens where
/// some box left its skin (a coil's turns slide 20 micrometres a step along
/// each other, a build every two or three steps); most pairs were kept
/// apart by their slack before it, and they are kept so after it.
class SlackBefore {
 public:
  /// Takes over c's slots, bodies and control points; reads its pairs'
  /// slack (none without a list: c null, or never built).
  explicit SlackBefore(PairCandidates* c) {
    if (!c || c->reach < 0.0 || c->pairs.size() != c->slack.size()) return;
    slot_.swap(c->slot);
    body_.swap(c->body);
    control_.swap(c->control);
    first_.assign(body_.size() + 1, 0);
    for (const auto& [k, l] : c->pairs) ++first_[std::min(k, l) + 1];
    for (size_t k = 1; k < first_.size(); ++k) first_[k] += first_[k - 1];
    entries_.resize(c->pairs.size());
    std::vector<int> fill(first_.begin(), first_.end() - 1);
    for (size_t q = 0; q < c->pairs.size(); ++q) {
      const auto [k, l] = c->pairs[q];
      entries_[fill[std::min(k, l)]++] = {std::max(k, l), c->slack[q]};
    }
  }
  /// The old index of element el, where it was there on the same body
  /// (-1: none), and how its axis moved since (control: its Bezier control
  /// points now).
  int oldIndex(const ElementRef& el, const std::array<Vec3, 4>& control,
               PairCandidates::Motion* motion) const {
    const int d = el.device, e = el.element;
    const int k = d < static_cast<int>(slot_.size()) && e < static_cast<int>(slot_[d].size())
                      ? slot_[d][e]
                      : -1;
    if (k < 0 || body_[k] != el.body) return -1;
    *motion = motionOf(control_[k], control);
    return k;
  }
  /// The slack of the old candidate (k, l) [m], or -inf.
  double slack(int k, int l) const {
    if (k < 0 || l < 0) return -std::numeric_limits<double>::infinity();
    const int lo = std::min(k, l), hi = std::max(k, l);
    for (int at = first_[lo]; at < first_[lo + 1]; ++at)
      if (entries_[at].first == hi) return entries_[at].second;
    return -std::numeric_limits<double>::infinity();
  }

 private:
  std::vector<std::vector<int>> slot_;
  std::vector<int> body_;
  std::vector<std::array<Vec3, 4>> control_;
  std::vector<int> first_;                       // per old element: its first entry
  std::vector<std::pair<int, double>> entries_;  // (the other's old index, slack [m])
};

/// Whether a candidate's bound [m] of its axes' distance (its slack, less
/// how far both axes moved since it was measured) keeps it apart: farther
/// than both radii and the margin, and farther than both axes moved in the
/// step (no swept test).
bool keptApart(double bound, double radii, double margin, bool swept_test, double sweeps) {
  return bound >= radii + margin && (!swept_test || sweeps < bound);
}

}  // namespace

/// Pairs of points, at least one of them free, closer than the sum of their
/// radii plus `margin`, from a grid of cells (CellRows). On one body (a
/// device, or either part of a detached one) only points more than 2 (r_a +
/// r_b) plus two element lengths apart along it count (neighbours along a
/// device always touch); the pusher's tip and the detached coil's end are
/// two bodies and touch as any pair. Per pair of elements the closest pair
/// only.
std::vector<PointPair> findPointPairs(const std::vector<DeviceModel>& devices,
                                      const std::vector<PointRef>& pts, double margin,
                                      PointCandidates* candidates) {
  std::vector<Candidate> found;
  // A pair within reach, by its indices in pts.
  auto check = [&](int i, int j) {
    // a: the lower index (the contact's first point), as a scan in index
    // order would make it.
    const int ia = std::min(i, j), ib = std::max(i, j);
    const PointRef& a = pts[ia];
    const PointRef& b = pts[ib];
    if (!a.free && !b.free) return;
    if (a.in_lumen_of == b.device || b.in_lumen_of == a.device) return;
    const double reach = a.r + b.r + margin;
    const double dist2 = (a.p - b.p).squaredNorm();
    if (dist2 >= reach * reach || dist2 == 0.0) return;
    if (a.device == b.device && a.body == b.body) {
      const double along = std::abs(a.s - b.s);
      const double le = std::max(devices[a.device].elements[a.element].length,
                                 devices[b.device].elements[b.element].length);
      if (along <= 2.0 * (a.r + b.r) + 2.0 * le) return;
    }
    const int64_t elements = static_cast<int64_t>(a.device) << 52 |
                             static_cast<int64_t>(a.element) << 32 |
                             static_cast<int64_t>(b.device) << 20 | b.element;
    found.push_back({elements, std::sqrt(dist2), ia, ib});
  };
  // The candidates of an earlier pass (of this step or an earlier one),
  // where every point now was, with its radius, and from where it moved
  // less than the skin: a pair within reach now was within reach plus
  // twice the skin there.
  std::vector<int> now;  // per point when built: its index in pts, or -1
  if (candidates && candidates->reach >= margin) {
    const PointCandidates& c = *candidates;
    const double skin2 = c.skin * c.skin;
    now.assign(c.at.size(), -1);
    for (size_t i = 0; i < pts.size(); ++i) {
      const int d = pts[i].device, k = pts[i].sample;
      const int at = d < static_cast<int>(c.slot.size()) && k < static_cast<int>(c.slot[d].size())
                         ? c.slot[d][k]
                         : -1;
      if (at < 0 || c.r[at] != pts[i].r || (pts[i].p - c.at[at]).squaredNorm() >= skin2) {
        now.clear();
        break;
      }
      now[at] = static_cast<int>(i);
    }
  }
  if (!now.empty()) {
    ++candidates->reuses;
    for (const auto& [k, l] : candidates->pairs)
      if (now[k] >= 0 && now[l] >= 0) check(now[k], now[l]);
    return closestPerElementPair(std::move(found));
  }
  double rmax = 0.0;
  for (const auto& q : pts) rmax = std::max(rmax, q.r);
  // Building the candidates: the pairs within reach plus twice the skin
  // (the largest radius: a coil's turns move some micrometres from pass to
  // pass and from step to step, its iterates tens of micrometres; on
  // aneurysm at t = 11-11.5 s a skin of half the radius rebuilt the grid in
  // half of the passes, 1.3x this one's instructions here, twice the
  // radius 1.2x), whatever their other tests, which are made on use.
  double grow = 0.0;
  if (candidates) {
    PointCandidates& c = *candidates;
    c.skin = rmax;
    c.reach = margin;
    grow = 2.0 * c.skin;
    c.slot.assign(devices.size(), {});
    c.at.resize(pts.size());
    c.r.resize(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      std::vector<int>& slot = c.slot[pts[i].device];
      if (static_cast<int>(slot.size()) <= pts[i].sample) slot.resize(pts[i].sample + 1, -1);
      slot[pts[i].sample] = static_cast<int>(i);
      c.at[i] = pts[i].p;
      c.r[i] = pts[i].r;
    }
    c.pairs.clear();
    ++c.builds;
  }
  std::vector<Vec3> at(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) at[i] = pts[i].p;
  const CellRows grid(at, 2.0 * rmax + margin + grow);
  grid.forNeighbours([&](int at_sorted, int k_sorted) {
    const int i = grid.sorted[at_sorted].second, j = grid.sorted[k_sorted].second;
    if (candidates) {
      const double reach = pts[i].r + pts[j].r + margin + grow;
      if ((pts[i].p - pts[j].p).squaredNorm() >= reach * reach) return;
      candidates->pairs.push_back({std::min(i, j), std::max(i, j)});
    }
    check(i, j);
  });
  return closestPerElementPair(std::move(found));
}

/// Pairs of elements, at least one of them free, whose axes come closer
/// than the sum of their radii plus `margin`: the elements whose boxes
/// (grown by their radii) come within the margin of each other, from a grid
/// of their centres (CellRows, cells as wide as the boxes in it, so that
/// each pair of boxes that can meet is looked at once), then, where a
/// lower bound of their axes' distance (axisGapBound) does not rule them
/// out, the closest points of their axes (closestAxisPoints). On one body
/// (a device, or either part of a detached one) only points more than
/// 2 (r_a + r_b) plus two element lengths apart along it count (neighbours
/// along a device always touch); the pusher's tip and the detached coil's end are two
/// bodies and touch as any pair. A closest point at an element's distal
/// node is left to the next element, whose proximal node it is: one
/// contact there, not two. Sorted by (device, element) pairs.
///
/// Given the step's start `from`, a pair whose axes moved (ElementRef::sweep
/// of both) by at least their distance at `from` (its lower bound,
/// axisGapBound) gets the swept test: firstTouch on the path that moves
/// each axis point straight from its place at `from` to its place at x
/// finds where they first came within the sum of their radii; a pair that
/// crossed after it is made a contact there (Pair::swept). A slower pair
/// cannot have crossed: its axes cannot have met.
std::vector<Pair> findPairs(const std::vector<DeviceModel>& devices,
                            const std::vector<DeviceState>& x, const std::vector<ElementRef>& els,
                            double margin, const StartAxes* from, bool apart_too,
                            PairCandidates* candidates) {
  const double reach = std::max(0.0, margin);
  std::vector<Pair> out;
  if (els.empty()) return out;
  // The candidates of an earlier pass (of this step or an earlier one),
  // where every element was, free or held and on its body as now (a
  // detachment makes the pusher's tip and the coil's end a pair to check,
  // no longer neighbours), and its box still lies
  // within its box there grown by the skin: a pair whose boxes come within
  // reach now came within reach plus twice the skin there.
  std::vector<int> now;  // per element when built: its index in els, or -1
  if (candidates && candidates->reach >= reach) {
    now.assign(candidates->box.size(), -1);
    for (size_t i = 0; i < els.size() && !now.empty(); ++i) {
      const auto& slot = candidates->slot;
      const int d = els[i].device, e = els[i].element;
      const int k = d < static_cast<int>(slot.size()) && e < static_cast<int>(slot[d].size())
                        ? slot[d][e]
                        : -1;
      if (k < 0 || candidates->free[k] != els[i].free || candidates->body[k] != els[i].body ||
          !candidates->box[k].contains(els[i].box))
        now.clear();
      else
        now[k] = static_cast<int>(i);
    }
  }
  // Checks a pair; *apart (when given) becomes a lower bound [m] of its
  // axes' distance where the check found one (boxes, axisGapBound), +inf
  // where the two are neighbours on one body for good.
  auto check = [&](int i, int j, double* apart = nullptr) {
    if (i < 0 || j < 0) return;  // (a candidate no longer in els)
    const int ia = std::min(i, j), ib = std::max(i, j);
    const ElementRef& a = els[ia];
    const ElementRef& b = els[ib];
    if (!a.free && !b.free) return;
    if (a.in_lumen_of == b.device || b.in_lumen_of == a.device) return;
    const double box_gap2 = a.box.squaredExteriorDistance(b.box);
    if (box_gap2 > reach * reach) {
      // Each box holds its axis grown by its radius.
      if (apart) *apart = std::sqrt(box_gap2) + a.point.radius + b.point.radius;
      return;
    }
    const DeviceModel& ma = devices[a.device];
    const DeviceModel& mb = devices[b.device];
    const double ra = a.point.radius, rb = b.point.radius;
    const bool one_body = a.device == b.device && a.body == b.body;
    const double exempt = one_body ? 2.0 * (ra + rb) + 2.0 * std::max(ma.elements[a.element].length,
                                                                      mb.elements[b.element].length)
                                   : 0.0;
    if (one_body) {  // every point pair of the two elements exempt: neighbours
      const double a0 = along(ma, a.element, 0.0), a1 = along(ma, a.element, 1.0);
      const double b0 = along(mb, b.element, 0.0), b1 = along(mb, b.element, 1.0);
      if (std::max(std::abs(a1 - b0), std::abs(b1 - a0)) <= exempt) {
        if (apart) *apart = std::numeric_limits<double>::infinity();
        return;
      }
    }
    const double gap = axisGapBound(a.axis, a.bow, b.axis, b.bow);
    if (apart) *apart = gap;
    // A pair whose axes moved relative to each other (at most `speed`: the
    // smaller of both sweeps and their relative shift plus both spreads) by
    // as much as they were apart at the step's start and at x may have met
    // in between and crossed: the swept test from the step's start.
    double speed = 0.0;
    bool swept = false;
    const HermiteAxis *from_a = nullptr, *from_b = nullptr;
    if (from && a.sweep + b.sweep >= gap) {
      speed = std::min(a.sweep + b.sweep, (a.shift - b.shift).norm() + a.spread + b.spread);
      from_a = &from->axis(a.device, a.element);
      from_b = &from->axis(b.device, b.element);
      swept = speed > 0.0 && speed >= gap &&
              speed >= axisGapBound(*from_a, from->bow(a.device, a.element), *from_b,
                                    from->bow(b.device, b.element));
    }
    if ((!swept || !apart_too) && gap >= ra + rb + margin) return;
    Pair pr{ia, ib, a.point, b.point, Vec3::Zero(), Vec3::Zero(), 0.0};
    const HermiteAxis& axis_a = a.axis;
    const HermiteAxis& axis_b = b.axis;
    pr.distance = closestAxisPoints(axis_a, axis_b, &pr.on_a.xi, &pr.on_b.xi);
    const bool near = pr.distance < ra + rb + margin;
    if (swept && (near || apart_too)) {
      // Crossed: the axes at x overlap with the normal turned against the
      // one where they first touched, or the points that touched there lie
      // beyond each other along it. The contact then holds those points on
      // the side they touched from (the plane at the first root, as on the
      // wall); otherwise the pair at x as without the test.
      const Touch t = firstTouch(*from_a, axis_a, *from_b, axis_b, ra + rb, speed);
      if (t.touched) {
        const Vec3 across = axis_a.at(t.xi_a).position - axis_b.at(t.xi_b).position;
        const bool turned =
            near &&
            (axis_a.at(pr.on_a.xi).position - axis_b.at(pr.on_b.xi).position).dot(t.normal) < 0.0;
        if (turned || (!near && across.dot(t.normal) < 0.0)) {
          pr.swept = true;
          pr.normal = t.normal;
          pr.on_a.xi = t.xi_a;
          pr.on_b.xi = t.xi_b;
          pr.distance = across.dot(t.normal);
        }
      }
      if (!near && !pr.swept) return;
    } else if (!near) {
      return;
    }
    if (one_body &&
        std::abs(along(ma, a.element, pr.on_a.xi) - along(mb, b.element, pr.on_b.xi)) <= exempt)
      return;
    if ((pr.on_a.xi == 1.0 && nextHoldsEnd(ma, x[a.device], a.element)) ||
        (pr.on_b.xi == 1.0 && nextHoldsEnd(mb, x[b.device], b.element)))
      return;
    pr.pa = samplePosition(ma, x[a.device], pr.on_a);
    pr.pb = samplePosition(mb, x[b.device], pr.on_b);
    out.push_back(pr);
  };
  auto byIndex = [](const Pair& p, const Pair& q) { return p.a != q.a ? p.a < q.a : p.b < q.b; };
  if (!now.empty()) {
    PairCandidates& c = *candidates;
    ++c.reuses;
    // How far each element's axis moved since the last pass, and what a
    // candidate's test reads of it, one array per quantity: an element
    // not in this pass moved "infinitely" (its candidates get no bound).
    PairCandidates::Reaches& r = c.reaches;
    r.resize(c.control.size());
    for (size_t k = 0; k < c.control.size(); ++k) {
      if (now[k] < 0) {
        r.x[k] = r.y[k] = r.z[k] = r.radius[k] = r.sweep[k] = 0.0;
        r.drift[k] = r.spread[k] = std::numeric_limits<double>::infinity();
        continue;
      }
      const ElementRef& el = els[now[k]];
      const std::array<Vec3, 4> at = controlPoints(el.axis);
      const PairCandidates::Motion m = motionOf(c.control[k], at);
      r.x[k] = m.shift.x(), r.y[k] = m.shift.y(), r.z[k] = m.shift.z();
      r.spread[k] = m.spread, r.drift[k] = m.drift;
      r.radius[k] = el.point.radius, r.sweep[k] = el.sweep;
      c.control[k] = at;
    }
    // Two passes over the candidates: every bound first (a tight loop that
    // the checks' code does not interrupt), then the checks of those it
    // leaves within reach.
    const size_t count = c.pairs.size();
    std::vector<int>& unsure = c.unsure;
    unsure.resize(count);
    size_t unsure_count = 0;
    const bool swept_test = from != nullptr;
    long kept = 0;
    for (size_t q = 0; q < count; ++q) {
      const int k = c.pairs[q][0], l = c.pairs[q][1];
      const double dx = r.x[k] - r.x[l], dy = r.y[k] - r.y[l], dz = r.z[k] - r.z[l];
      const double bound = c.slack[q] - relativeMotion(r.drift[k], r.drift[l],
                                                       std::sqrt(dx * dx + dy * dy + dz * dz),
                                                       r.spread[k], r.spread[l]);
      const bool apart =
          keptApart(bound, r.radius[k] + r.radius[l], margin, swept_test, r.sweep[k] + r.sweep[l]);
      c.slack[q] = apart ? bound : c.slack[q];
      kept += apart;
      unsure[unsure_count] = static_cast<int>(q);
      unsure_count += !apart;
    }
    c.kept_apart += kept;
    for (size_t u = 0; u < unsure_count; ++u) {
      const int q = unsure[u];
      const int i = now[c.pairs[q][0]], j = now[c.pairs[q][1]];
      double apart = -std::numeric_limits<double>::infinity();
      if (i >= 0 && j >= 0) check(i, j, &apart);  // (else not measured in this pass: no bound kept)
      c.slack[q] = apart;
    }
    std::sort(out.begin(), out.end(), byIndex);
    return out;
  }
  // Cells as wide as the widest box up to twice the width of nine in ten:
  // the few far wider ones (a pusher's or a catheter's long elements among
  // a coil's short ones) are tested against every element instead, so that
  // they do not coarsen the grid. (Cells of the nine-in-ten width made a
  // tenth of a coil's elements, bowed a little more, "wide": 58 of 582 in
  // aneurysm_packed, each tested against all others, 30,000 box tests a
  // build.)
  std::vector<double> widths(els.size());
  for (size_t i = 0; i < els.size(); ++i) widths[i] = els[i].box.sizes().maxCoeff();
  std::vector<double> sorted = widths;
  const size_t q = sorted.size() * 9 / 10;
  std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
  double cell_width = 0.0;
  for (double w : widths)
    if (w <= 2.0 * sorted[q]) cell_width = std::max(cell_width, w);
  std::vector<Vec3> centres;
  std::vector<int> small, large;
  for (size_t i = 0; i < els.size(); ++i) {
    if (widths[i] <= cell_width) {
      small.push_back(static_cast<int>(i));
      centres.push_back(els[i].box.center());
    } else {
      large.push_back(static_cast<int>(i));
    }
  }
  // Building the candidates: every element's box grown by the skin (a
  // tenth of the cells), the pairs of those within reach, then checked.
  double grow = 0.0;
  std::vector<int> old_index;                  // per element: its index in the list replaced, or -1
  std::vector<PairCandidates::Motion> motion;  // and how its axis moved since
  SlackBefore before(candidates);              // (before the list below replaces it)
  if (candidates) {
    PairCandidates& c = *candidates;
    c.skin = 0.1 * cell_width;
    c.reach = reach;
    grow = 2.0 * c.skin;
    c.slot.assign(devices.size(), {});
    for (size_t d = 0; d < devices.size(); ++d) c.slot[d].assign(devices[d].num_nodes - 1, -1);
    c.box.resize(els.size());
    c.free.resize(els.size());
    c.body.resize(els.size());
    c.control.resize(els.size());
    old_index.assign(els.size(), -1);
    motion.assign(els.size(), {Vec3::Zero(), 0.0, 0.0});
    for (size_t i = 0; i < els.size(); ++i) {
      c.slot[els[i].device][els[i].element] = static_cast<int>(i);
      c.box[i] =
          Eigen::AlignedBox3d(els[i].box.min().array() - c.skin, els[i].box.max().array() + c.skin);
      c.free[i] = els[i].free;
      c.body[i] = els[i].body;
      c.control[i] = controlPoints(els[i].axis);
      old_index[i] = before.oldIndex(els[i], c.control[i], &motion[i]);
    }
    c.pairs.clear();
    ++c.builds;
  }
  auto consider = [&](int i, int j) {
    if (!candidates) return check(i, j);
    if ((els[i].free || els[j].free) &&
        candidates->box[i].squaredExteriorDistance(candidates->box[j]) <= reach * reach)
      candidates->pairs.push_back({i, j});
  };
  for (size_t k = 0; k < large.size(); ++k) {
    for (int j : small) consider(large[k], j);
    for (size_t l = k + 1; l < large.size(); ++l) consider(large[k], large[l]);
  }
  if (!small.empty()) {
    const CellRows grid(centres, cell_width + reach + grow);
    auto considerCells = [&](int at, int k) {
      consider(small[grid.sorted[at].second], small[grid.sorted[k].second]);
    };
    grid.forNeighbours(considerCells);
  }
  if (candidates) {
    std::vector<double>& slack = candidates->slack;
    slack.assign(candidates->pairs.size(), -std::numeric_limits<double>::infinity());
    for (size_t q = 0; q < slack.size(); ++q) {
      const auto [i, j] = candidates->pairs[q];
      const double bound =
          before.slack(old_index[i], old_index[j]) - relativeMotion(motion[i], motion[j]);
      if (keptApart(bound, els[i].point.radius + els[j].point.radius, margin, from != nullptr,
                    els[i].sweep + els[j].sweep)) {
        slack[q] = bound;
        ++candidates->kept_apart;
        ++candidates->carried;
        continue;
      }
      check(i, j, &slack[q]);
    }
  }
  std::sort(out.begin(), out.end(), byIndex);
  return out;
}

}  // namespace pairs
}  // namespace evsim
