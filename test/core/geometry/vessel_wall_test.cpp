// The vessel wall's model (geometry/vessel_wall.h) against closed forms: a
// tethered tube under a point force is Hetenyi's beam on an elastic
// foundation, a uniform load relaxes as the tether's first-order law, and a
// pressurised tube widens as Lame's thick-walled cylinder does in its
// thin-walled limit.
#include "endovascular_sim/geometry/vessel_wall.h"

#include <gtest/gtest.h>

#include <cmath>

namespace evsim {
namespace {

/// A straight tube of n points spaced h [m] along `axis` (unit), radius r.
Centerline straightTube(int n, double h, const Vec3& axis, double r) {
  Centerline c;
  for (int i = 0; i < n; ++i) {
    c.position.push_back(i * h * axis);
    c.radius.push_back(r);
    c.parent.push_back(i - 1);
    c.type.push_back(0);
    c.vessel.push_back(0);
  }
  c.vessel_names = {"tube"};
  return c;
}

// A wall of Young's modulus E and thickness h_w: D = 2 R / (E h_w) for the
// model, and Hetenyi's solution with the thin tube's own second moment of
// area, I = pi R^3 h_w.
TEST(VesselWall, PointForceOnATetheredTubeIsHetenyisBeamOnAnElasticFoundation) {
  const double R = 3.5e-3, wall_e = 0.8e6, wall_h = 0.7e-3;  // [m], [Pa], [m]
  WallProperties p;
  p.distensibility = 2 * R / (wall_e * wall_h);
  p.tether_stiffness = 5e3;
  const double ei = wall_e * M_PI * R * R * R * wall_h;
  const double beta = std::pow(p.tether_stiffness / (4 * ei), 0.25);  // [1/m]
  const int n = 801;                                                  // 40 decay lengths
  const double h = 1 / (20 * beta);
  const Vec3 axis = Vec3(1, 2, 2) / 3, across = Vec3(2, 1, -2) / 3;
  const Centerline c = straightTube(n, h, axis, R);
  const VesselWall wall(c, {p});
  EXPECT_NEAR(wall.bendingStiffness(n / 2), ei, 1e-12 * ei);

  const double force = 0.1;  // [N]
  std::vector<Vec3> loads(n, Vec3::Zero());
  loads[n / 2] = force * across;
  const std::vector<Vec3> u = wall.equilibrium(loads);
  const double w0 = force * beta / (2 * p.tether_stiffness);
  double worst = 0.0;
  int checked = 0;
  for (int i = 0; i < n; ++i) {
    const double x = std::abs(i - n / 2) * h;
    if (beta * x > 5) continue;
    const double w = w0 * std::exp(-beta * x) * (std::cos(beta * x) + std::sin(beta * x));
    worst = std::max(worst, std::abs(u[i].dot(across) - w));
    EXPECT_NEAR(u[i].dot(axis), 0.0, 1e-12 * w0);  // no stretch under a transverse load
    ++checked;
  }
  EXPECT_EQ(checked, 201);
  EXPECT_LT(worst, 0.01 * w0) << "worst deflection error " << worst << " m of w(0) = " << w0;
}

TEST(VesselWall, AUniformLoadRelaxesAsTheTethersFirstOrderLaw) {
  WallProperties p;
  p.tether_stiffness = 4e3;
  p.tether_damping = 20.0;
  const int n = 50;
  const double h = 1e-3, q = 2.0;  // [m], [N/m]
  const Centerline c = straightTube(n, h, Vec3::UnitX(), 2e-3);
  const VesselWall wall(c, {p});
  std::vector<Vec3> loads(n);
  for (int i = 0; i < n; ++i) loads[i] = Vec3(0, 0, q * wall.nodeLength(i));
  const double tau = p.tether_damping / p.tether_stiffness;  // [s]
  const double dt = tau / 1000;
  VesselWall::StepFactor factor;
  std::vector<Vec3> u;
  for (int s = 0; s < 1000; ++s) wall.step(loads, dt, &factor, &u);
  // Implicit Euler's own answer, and the exact law, one time constant on.
  const double discrete = q / p.tether_stiffness * (1 - std::pow(1 + dt / tau, -1000));
  const double exact = q / p.tether_stiffness * (1 - std::exp(-1.0));
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(u[i].z(), discrete, 1e-9 * discrete) << i;
    EXPECT_NEAR(u[i].z(), exact, 1e-3 * exact) << i;
    EXPECT_NEAR(u[i].x(), 0.0, 1e-12);
  }
}

// Lame: a cylinder of inner radius a and outer b under internal pressure p
// (plane stress) moves its bore by p a^2 ((1 - nu) a^2 + (1 + nu) b^2) /
// (E a (b^2 - a^2)); as b -> a the model's dR = p R^2 / (E h).
TEST(VesselWall, APressurisedTubeWidensAsLamesCylinderInItsThinWalledLimit) {
  const double a = 3e-3, wall_h = 3e-6, wall_e = 1e6, nu = 0.45, pressure = 1e3;
  const double b = a + wall_h;
  const double lame =
      pressure * a * ((1 - nu) * a * a + (1 + nu) * b * b) / (wall_e * (b * b - a * a));
  WallProperties p;
  p.distensibility = 2 * a / (wall_e * wall_h);
  const VesselWall wall(straightTube(3, 1e-3, Vec3::UnitY(), a), {p});
  const double load_per_length = pressure * 2 * M_PI * a;  // [N/m]
  EXPECT_NEAR(wall.radiusChange(1, load_per_length), lame, 0.01 * lame);
}

}  // namespace
}  // namespace evsim
