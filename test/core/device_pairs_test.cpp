// The grid search of device point pairs (contact/device_pairs.h) against a
// brute-force scan of every pair, on random dense clouds of points of two
// devices (self-pairs and pairs between devices, held points, lumens).
#include "contact/device_pairs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

namespace evsim {
namespace {

using pairs::Pair;
using pairs::PointRef;

/// Every pair i < j, kept under the documented rules: one point free, not
/// in the other device's lumen, closer than r_i + r_j + margin and not
/// coincident, on one device more than 2 (r_i + r_j) + 2 element lengths
/// apart along it; per element pair the closest (lowest indices on ties).
std::vector<Pair> bruteForcePairs(const std::vector<DeviceModel>& devices,
                                  const std::vector<PointRef>& pts, double margin) {
  std::map<std::tuple<int, int, int, int>, Pair> best;
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
      const Pair p{static_cast<int>(i), static_cast<int>(j), std::sqrt((a.p - b.p).squaredNorm())};
      if (it == best.end() || p.distance < it->second.distance) best[key] = p;
    }
  }
  std::vector<Pair> out;
  for (const auto& [key, p] : best) out.push_back(p);
  return out;
}

TEST(DevicePairs, GridSearchFindsExactlyTheBruteForcePairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double element_length = 5e-4;  // [m]
  std::vector<DeviceModel> devices(2);
  for (auto& d : devices) d.elements.assign(300, BeamElementRest{element_length});
  int compared = 0, found = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const double box = 2e-3 + 4e-3 * u(rng);  // [m] edge of the cloud (dense to sparse)
    std::vector<PointRef> pts;
    for (int device = 0; device < 2; ++device)
      for (int e = 0; e < 300; ++e) {
        const Vec3 p = box * Vec3(u(rng), u(rng), u(rng)) - Vec3::Constant(box / 2);
        pts.push_back({u(rng) < 0.9, device, e, e, e * element_length, p, 1e-4 + 5e-5 * u(rng),
                       device == 1 && u(rng) < 0.2 ? 0 : -1});
      }
    for (double margin : {0.0, -1e-6, 5e-5}) {
      const std::vector<Pair> grid = pairs::findPairs(devices, pts, margin);
      const std::vector<Pair> brute = bruteForcePairs(devices, pts, margin);
      ASSERT_EQ(grid.size(), brute.size()) << "trial " << trial << " margin " << margin;
      for (size_t k = 0; k < grid.size(); ++k) {
        EXPECT_EQ(grid[k].a, brute[k].a);
        EXPECT_EQ(grid[k].b, brute[k].b);
        EXPECT_EQ(grid[k].distance, brute[k].distance);
      }
      ++compared;
      found += static_cast<int>(grid.size());
    }
  }
  EXPECT_EQ(compared, 60);
  EXPECT_GT(found, 1000);  // the clouds are dense enough to test something
  std::printf("[ metric   ] %d pairs found in 60 clouds, all equal to the brute force\n", found);
}

}  // namespace
}  // namespace evsim
