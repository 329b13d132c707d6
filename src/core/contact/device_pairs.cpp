// Pairs of device sample points closer than the sum of their radii (the effect
// 'device_contact'; internal to the contact solver, contact_solver.cpp).
// Declared and documented in device_pairs.h.
#include "device_pairs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace evsim {
namespace pairs {

/// Normal of a contact between two device points, from b to a: across both
/// axes (crossed cylinders: t_a x t_b), or, for nearly parallel axes, the
/// part of p_a - p_b across t_a. Point-to-point normals would make each
/// contact a pair of spheres, which roll off each other.
Vec3 pairNormal(const Vec3& pa, const Vec3& ta, const Vec3& pb, const Vec3& tb) {
  const Vec3 d = pa - pb;
  const Vec3 c = ta.cross(tb);
  if (c.norm() > 0.1) {
    const Vec3 n = c.normalized();
    return n.dot(d) >= 0.0 ? n : Vec3(-n);
  }
  const Vec3 across = d - d.dot(ta) * ta;
  return across.norm() > 0.0 ? Vec3(across.normalized()) : d.normalized();
}

namespace {

constexpr int64_t kLow21 = (int64_t{1} << 21) - 1;

/// The points sorted by grid cell, key (z, y, x) with x least significant:
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

  CellRows(const std::vector<PointRef>& pts, double cell) {
    auto cellOf = [cell](double v) {
      return static_cast<int64_t>(std::floor(v / cell)) + (1 << 20);
    };
    const int n = static_cast<int>(pts.size());
    sorted.resize(n);
    for (int i = 0; i < n; ++i)
      sorted[i] = {cellOf(pts[i].p.z()) << 42 | cellOf(pts[i].p.y()) << 21 | cellOf(pts[i].p.x()),
                   i};
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
};

/// A pair of points within reach, with its pair of elements.
struct Candidate {
  int64_t elements;  // (device a, element a, device b, element b) packed
  double distance;
  int a, b;
};

/// Per pair of elements the closest candidate (the first index pair on
/// ties, as a scan in index order would keep).
std::vector<Pair> closestPerElementPair(std::vector<Candidate> found) {
  std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) {
    if (x.elements != y.elements) return x.elements < y.elements;
    if (x.distance != y.distance) return x.distance < y.distance;
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  std::vector<Pair> out;
  for (size_t k = 0; k < found.size(); ++k)
    if (k == 0 || found[k].elements != found[k - 1].elements)
      out.push_back({found[k].a, found[k].b, found[k].distance});
  return out;
}

}  // namespace

/// Pairs of points, at least one of them free, closer than the sum of their
/// radii plus `margin`, from a grid of cells (CellRows). On one body (a
/// device, or either part of a detached one) only points more than 2 (r_a +
/// r_b) plus two element lengths apart along it count (neighbours along a
/// device always touch); the pusher's tip and the detached coil's end are
/// two bodies and touch as any pair. Per pair of elements the closest pair
/// only.
std::vector<Pair> findPairs(const std::vector<DeviceModel>& devices,
                            const std::vector<PointRef>& pts, double margin) {
  double rmax = 0.0;
  for (const auto& q : pts) rmax = std::max(rmax, q.r);
  const CellRows grid(pts, 2.0 * rmax + margin);
  std::vector<Candidate> found;
  auto check = [&](int at, int k) {
    const int i = grid.sorted[at].second, j = grid.sorted[k].second;
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
  // Each pair of cells is visited once, row against row (both in x order,
  // so a window x - 1 ... x + 1 slides along the other row): a row with
  // itself (a point against the later points of its cell and of x + 1),
  // and with the rows (z, y + 1) and (z + 1, y - 1 ... y + 1), looked up
  // once a row, not once a point.
  constexpr int64_t kRowStep[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
  for (const CellRows::Row& row : grid.rows) {
    for (int at = row.begin; at < row.end; ++at)
      for (int k = at + 1; k < row.end && grid.x(k) <= grid.x(at) + 1; ++k) check(at, k);
    const int64_t y = row.key & kLow21, z = row.key >> 21;
    for (const auto& step : kRowStep) {
      const CellRows::Row& other = grid.row(z + step[0], y + step[1]);
      if (other.key == -1) continue;
      int first = other.begin;  // the first point of the other row at x - 1 or beyond
      for (int at = row.begin; at < row.end; ++at) {
        const int64_t x = grid.x(at);
        while (first < other.end && grid.x(first) < x - 1) ++first;
        for (int k = first; k < other.end && grid.x(k) <= x + 1; ++k) check(at, k);
      }
    }
  }
  return closestPerElementPair(std::move(found));
}

}  // namespace pairs
}  // namespace evsim
