// The shipped anatomy: aneurysm dimensions in clinical ranges, and the
// generated network's size, determinism and Murray's law.
#include <gtest/gtest.h>

#include <cstdio>

#include "endovascular_sim/geometry/network_generator.h"
#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {
namespace {

TEST(AneurysmScene, DomeAndNeckAreInClinicalRanges) {
  const SceneSpec spec = loadSceneFile(configDirectory() + "/scenes/aneurysm.yaml");
  const VesselField f = buildVesselField(spec.vessels, false);
  ASSERT_EQ(spec.vessels.aneurysms.size(), 1u);
  const Vec3 c = spec.vessels.aneurysms[0].center;
  // Dome: height from the vessel's outer wall to the top, width across.
  const SurfacePoint top = firstRoot(f, c, c + Vec3(0, 0, 0.02), 0.0);
  const SurfacePoint side_a = firstRoot(f, c, c + Vec3(0, 0.02, 0), 0.0);
  const SurfacePoint side_b = firstRoot(f, c, c - Vec3(0, 0.02, 0), 0.0);
  ASSERT_TRUE(top.hit && side_a.hit && side_b.hit);
  const double width = (side_a.point - side_b.point).norm();
  // Neck: the narrowest width of the lumen across the opening, between the
  // vessel's top (z = 10.2 mm) and the dome's centre, in the plane y = 0.
  double neck = 1e9;
  for (double z = 0.0102; z < c.z(); z += 1e-4) {
    const Vec3 mid(c.x(), 0.0, z);
    if (f.evaluate(mid, 0.0).value < 0.0) continue;
    const SurfacePoint a = firstRoot(f, mid, mid + Vec3(0.02, 0, 0), 0.0);
    const SurfacePoint b = firstRoot(f, mid, mid - Vec3(0.02, 0, 0), 0.0);
    if (a.hit && b.hit) neck = std::min(neck, (a.point - b.point).norm());
  }
  std::printf(
      "[ metric   ] aneurysm: dome width %.2f mm, top %.2f mm above its centre, neck %.2f mm\n",
      width * 1e3, (top.point.z() - c.z()) * 1e3, neck * 1e3);
  EXPECT_GT(width, 5e-3);  // saccular aneurysms treated by coiling: dome 5-10 mm
  EXPECT_LT(width, 10e-3);
  EXPECT_GT(neck, 2e-3);  // neck 2-5 mm; the dome is wider than the neck
  EXPECT_LT(neck, 5e-3);
  EXPECT_GT(width / neck, 1.2);
}

TEST(Network, DeterministicFromTheSeedWithMurraysLaw) {
  const Centerline base = loadCenterlineFile(configDirectory() + "/vessels/carotid.swc");
  NetworkOptions o;
  o.vessels = 4000;
  Centerline a = base, b = base, other = base;
  EXPECT_GE(growNetwork(o, &a), 4000);
  growNetwork(o, &b);
  o.seed = 8;
  growNetwork(o, &other);
  ASSERT_EQ(a.numPoints(), b.numPoints());
  for (int i = 0; i < a.numPoints(); ++i) EXPECT_EQ(a.position[i], b.position[i]);
  EXPECT_NE(a.position.back(), other.position.back());
  // Murray: at every generated bifurcation r_p^3 = r_1^3 + r_2^3.
  std::vector<std::vector<int>> children(a.numPoints());
  for (int i = base.numPoints(); i < a.numPoints(); ++i) children[a.parent[i]].push_back(i);
  int checked = 0;
  for (int p = 0; p < a.numPoints(); ++p) {
    if (children[p].size() != 2 || children[p][0] < base.numPoints()) continue;
    const double r1 = a.radius[children[p][0]], r2 = a.radius[children[p][1]];
    EXPECT_NEAR(std::pow(a.radius[p], 3), r1 * r1 * r1 + r2 * r2 * r2,
                1e-9 * std::pow(a.radius[p], 3));
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace evsim
