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

/// Pairs of points, at least one of them free, closer than the sum of their
/// radii plus `margin`, from a grid of cells (sorted keys). On
/// one device only points more than 2 (r_a + r_b) plus two element lengths
/// apart along it count (neighbours along a device always touch). Per pair
/// of elements the closest pair only.
std::vector<Pair> findPairs(const std::vector<DeviceModel>& devices,
                            const std::vector<PointRef>& pts, double margin) {
  double rmax = 0.0;
  for (const auto& q : pts) rmax = std::max(rmax, q.r);
  const double cell = 2.0 * rmax + margin;
  // Cell key (z, y, x), x least significant: the points sorted by key lie
  // row by row ((z, y) fixed), each row in x order. A hash of the rows
  // (open addressing) gives each row's range; the neighbours of a point are
  // in 9 rows, at x - 1 ... x + 1 (of which the scan below visits half).
  auto cellOf = [cell](double v) { return static_cast<int64_t>(std::floor(v / cell)) + (1 << 20); };
  const int n = static_cast<int>(pts.size());
  std::vector<std::pair<int64_t, int>> sorted(n);  // (cell key, point)
  for (int i = 0; i < n; ++i)
    sorted[i] = {cellOf(pts[i].p.z()) << 42 | cellOf(pts[i].p.y()) << 21 | cellOf(pts[i].p.x()), i};
  std::sort(sorted.begin(), sorted.end());
  int bits = 4;
  while ((1 << bits) < 2 * n) ++bits;
  const uint64_t mask = (uint64_t{1} << bits) - 1;
  struct Row {
    int64_t key{-1};  // (z, y)
    int begin{0}, end{0};
  };
  std::vector<Row> rows(mask + 1);
  auto slot = [&](int64_t row_key) {
    uint64_t h = (static_cast<uint64_t>(row_key) * 0x9E3779B97F4A7C15ull) >> (64 - bits);
    while (rows[h].key != -1 && rows[h].key != row_key) h = (h + 1) & mask;
    return h;
  };
  std::vector<Row> row_list;  // the rows in sorted order
  for (int k = 0; k < n;) {
    const int64_t row_key = sorted[k].first >> 21;
    int e = k;
    while (e < n && (sorted[e].first >> 21) == row_key) ++e;
    rows[slot(row_key)] = {row_key, k, e};
    row_list.push_back({row_key, k, e});
    k = e;
  }
  struct Candidate {
    int64_t elements;  // (device a, element a, device b, element b) packed
    double distance;
    int a, b;
  };
  std::vector<Candidate> found;
  constexpr int64_t kLow21 = (int64_t{1} << 21) - 1;
  auto xOf = [&](int k) { return sorted[k].first & kLow21; };
  auto check = [&](int at, int k) {
    const int i = sorted[at].second, j = sorted[k].second;
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
    if (a.device == b.device) {
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
  constexpr int kNeighbourRows = 4;
  constexpr int64_t kRowStep[kNeighbourRows][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
  for (const Row& row : row_list) {
    for (int at = row.begin; at < row.end; ++at)
      for (int k = at + 1; k < row.end && xOf(k) <= xOf(at) + 1; ++k) check(at, k);
    const int64_t y = row.key & kLow21, z = row.key >> 21;
    for (const auto& step : kRowStep) {
      const Row& other = rows[slot((z + step[0]) << 21 | (y + step[1]))];
      if (other.key == -1) continue;
      int first = other.begin;  // the first point of the other row at x - 1 or beyond
      for (int at = row.begin; at < row.end; ++at) {
        const int64_t x = xOf(at);
        while (first < other.end && xOf(first) < x - 1) ++first;
        for (int k = first; k < other.end && xOf(k) <= x + 1; ++k) check(at, k);
      }
    }
  }
  // Per pair of elements the closest (the first index pair on ties, as a
  // scan in index order would keep).
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

}  // namespace pairs
}  // namespace evsim
