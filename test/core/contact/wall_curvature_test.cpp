// The wall-curvature term's tensor against analytic curvatures: inside a
// straight tube (1 / radius around it, 0 along it), on a plane (0), and
// inside a sphere (1 / radius in every tangent direction).
#include "endovascular_sim/contact/wall_curvature.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/geometry/vessel_field.h"

namespace evsim {
namespace {

Centerline straightTube(double rho) {
  Centerline c;
  for (int i = 0; i <= 40; ++i) {
    c.position.push_back(Vec3(-0.2 + 0.01 * i, 0.0, 0.0));
    c.radius.push_back(rho);
    c.parent.push_back(i - 1);
    c.type.push_back(0);
  }
  return c;
}

/// The wall point found from the axis along `dir` and its normal.
SurfacePoint wallAlong(const ImplicitSurface& s, const Vec3& from, const Vec3& dir, double r) {
  return firstRoot(s, from, from + 0.05 * dir, r);
}

TEST(WallCurvature, AroundATubeOneOverItsRadiusAlongItZero) {
  const double rho = 2e-3, r = 0.18e-3;
  const VesselField f(straightTube(rho), {}, {}, {});
  const SurfacePoint w = wallAlong(f, Vec3(0.005, 0, 0), Vec3(0, 0.6, -0.8), r);
  ASSERT_TRUE(w.hit);
  std::array<Vec3, 2> t;
  const Eigen::Matrix2d S = wallCurvature(f, w.point, w.normal, r, {}, &t);
  const Vec3 axis = Vec3::UnitX(), around = axis.cross(w.normal).normalized();
  auto curvatureAlong = [&](const Vec3& d) {
    const Eigen::Vector2d c(t[0].dot(d), t[1].dot(d));
    return c.dot(S * c);
  };
  EXPECT_NEAR(curvatureAlong(around), 1.0 / (rho - r), 1e-3 / (rho - r));
  EXPECT_NEAR(curvatureAlong(axis), 0.0, 1e-3 / (rho - r));
}

TEST(WallCurvature, APlaneAddsNothingASphereEverywhere) {
  const PlaneSurface floor(Vec3::Zero(), Vec3::UnitZ());
  std::array<Vec3, 2> t;
  EXPECT_NEAR(wallCurvature(floor, Vec3(0.1, 0.2, 0.0), Vec3::UnitZ(), 0.0, {}, &t).norm(), 0.0,
              1e-9);
  // An aneurysm dome alone, far from any vessel: a sphere of radius R - r.
  const double R = 3.5e-3, r = 0.1e-3;
  const VesselField dome(Centerline{}, {{Vec3(0.0, 0.0, 0.0), R}}, {}, {});
  const SurfacePoint w = wallAlong(dome, Vec3::Zero(), Vec3(0.0, 0.0, 1.0), r);
  ASSERT_TRUE(w.hit);
  const Eigen::Matrix2d S = wallCurvature(dome, w.point, w.normal, r, {}, &t);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
  const double radius = (w.point).norm();  // the sphere's iso radius for this device
  EXPECT_NEAR(eig.eigenvalues()(0), 1.0 / radius, 1e-3 / radius);
  EXPECT_NEAR(eig.eigenvalues()(1), 1.0 / radius, 1e-3 / radius);
}

}  // namespace
}  // namespace evsim
