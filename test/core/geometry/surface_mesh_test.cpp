// The display mesh against the geometry it meshes.
#include "endovascular_sim/geometry/surface_mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

namespace evsim {
namespace {

VesselField straightTube(double rho, double half_length) {
  Centerline c;
  for (int i = 0; i <= 10; ++i) {
    c.position.push_back(Vec3(-half_length + 2 * half_length * i / 10, 0, 0));
    c.radius.push_back(rho);
    c.parent.push_back(i - 1);
    c.type.push_back(0);
  }
  return VesselField(c, {}, {}, {});
}

TEST(SurfaceMesh, StraightTubeIsClosedWithTheRightRadiusAndVolume) {
  const double rho = 2e-3, h = 0.2e-3;
  const VesselField f = straightTube(rho, 0.02);
  const SurfaceMesh m = meshVesselSurface(f, h);
  ASSERT_GT(m.triangles.size(), 1000u);
  // Closed and consistently oriented: each directed edge appears once and
  // its reverse once.
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  // Away from the rounded ends, vertices lie on the radius (linear
  // interpolation error ~ h^2 / rho).
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const Vec3& p = m.vertices[i];
    if (std::abs(p.x()) > 0.015) continue;
    EXPECT_NEAR(p.tail<2>().norm(), rho, 0.02 * rho);
    EXPECT_GT(m.normals[i].dot(Vec3(0, p.y(), p.z()).normalized()), 0.99);  // outward
  }
  // Enclosed volume (divergence theorem) against a cylinder of the inner
  // length plus the two rounded ends, which are measured from the field.
  double volume = 0.0;
  for (const auto& t : m.triangles)
    volume += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  EXPECT_GT(volume, 0.0);  // outward orientation
  EXPECT_NEAR(volume, M_PI * rho * rho * 0.04, 0.1 * M_PI * rho * rho * 0.04);
}

TEST(SurfaceMesh, WritesPlyAndStl) {
  const SurfaceMesh m = meshVesselSurface(straightTube(1e-3, 0.005), 0.25e-3);
  const auto dir = std::filesystem::temp_directory_path();
  std::string why;
  ASSERT_TRUE(writeMesh(m, (dir / "evsim_mesh_test.ply").string(), &why)) << why;
  ASSERT_TRUE(writeMesh(m, (dir / "evsim_mesh_test.stl").string(), &why)) << why;
  EXPECT_EQ(std::filesystem::file_size(dir / "evsim_mesh_test.stl"), 84 + 50 * m.triangles.size());
  std::ifstream ply(dir / "evsim_mesh_test.ply");
  std::string first;
  ply >> first;
  EXPECT_EQ(first, "ply");
  EXPECT_FALSE(writeMesh(m, (dir / "evsim_mesh_test.obj").string(), &why));
  EXPECT_NE(why.find(".ply or .stl"), std::string::npos);
}

}  // namespace
}  // namespace evsim
