// The convolution field against independent answers.
#include "endovascular_sim/geometry/vessel_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "endovascular_sim/geometry/root_finding.h"

namespace evsim {
namespace {

/// A straight centreline along x from x0 to x1 [m], n segments, radius rho.
Centerline straightVessel(double x0, double x1, int n, double rho, Vec3 offset = Vec3::Zero()) {
  Centerline c;
  for (int i = 0; i <= n; ++i) {
    c.position.push_back(offset + Vec3(x0 + (x1 - x0) * i / n, 0.0, 0.0));
    c.radius.push_back(rho);
    c.parent.push_back(i - 1);
    c.type.push_back(0);
  }
  return c;
}

/// Composite Simpson quadrature of the segment integral (the closed form's
/// independent reference).
double segmentFieldByQuadrature(const Vec3& a, const Vec3& b, double R, const Vec3& p) {
  const int n = 200000;
  const double L = (b - a).norm();
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = L * i / n;
    const double r2 = (p - a - t * (b - a) / L).squaredNorm() / (R * R);
    const double k = r2 < 1.0 ? std::pow(1.0 - r2, 3) : 0.0;
    sum += k * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  return sum * (L / n) / 3.0 / R;
}

TEST(Kernel, SegmentClosedFormMatchesQuadrature) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-3e-3, 3e-3);
  const Vec3 a(0.0, 0.0, 0.0), b(4e-3, 1e-3, -2e-3);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(u(rng) + 2e-3, u(rng), u(rng));
    FieldSample s;
    addSegmentField(a, b, 2.5e-3, p, &s);
    EXPECT_NEAR(s.value, segmentFieldByQuadrature(a, b, 2.5e-3, p), 1e-9);
  }
}

TEST(Kernel, InfiniteLineProfile) {
  // Far from the ends, the profile is (32/35)(1 - d^2/R^2)^(7/2).
  const double R = 3e-3;
  for (double d : {0.0, 0.5e-3, 1.5e-3, 2.9e-3}) {
    FieldSample s;
    addSegmentField(Vec3(-1.0, 0, 0), Vec3(1.0, 0, 0), R, Vec3(0.0, d, 0.0), &s);
    EXPECT_NEAR(s.value, 32.0 / 35.0 * std::pow(1.0 - d * d / (R * R), 3.5), 1e-12);
  }
}

TEST(VesselField, GradientMatchesCentralDifferences) {
  Centerline c = straightVessel(-0.01, 0.01, 4, 2e-3);
  Centerline branch = straightVessel(0.0, 0.012, 3, 1.2e-3);
  for (auto& p : branch.position) p = Vec3(p.x() * 0.6, p.x() * 0.8, 0.0);
  branch.parent[0] = -1;
  c.append(branch);
  const VesselField f(c, {{Vec3(0.0, -3e-3, 1e-3), 2e-3}}, {}, {});
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-4e-3, 4e-3);
  int checked = 0;
  for (int k = 0; k < 500; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const FieldSample s = f.evaluate(p, 1e-4);
    if (s.gradient.norm() == 0.0) continue;
    const double h = 1e-7;
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = h * Vec3::Unit(j);
      const double fd = (f.evaluate(p + e, 1e-4).value - f.evaluate(p - e, 1e-4).value) / (2 * h);
      EXPECT_NEAR(s.gradient[j], fd, 1e-6 * s.gradient.norm() + 1e-3);
    }
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

double isoRadiusAt(const VesselField& f, const Vec3& centre, const Vec3& dir, double r_dev) {
  const SurfacePoint s = firstRoot(f, centre, centre + 0.05 * dir, r_dev);
  EXPECT_TRUE(s.hit);
  return (s.point - centre).norm();
}

TEST(VesselField, RadiusFidelityAlongStraightVessels) {
  for (double rho : {0.6e-3, 3.5e-3, 12e-3}) {
    const VesselField f(straightVessel(-0.2, 0.2, 40, rho), {}, {}, {});
    for (double r_dev : {0.0, 0.18e-3}) {
      for (double x : {0.0, 0.005, 0.0321}) {  // a joint, inside a segment
        for (const Vec3& dir : {Vec3(0, 1, 0), Vec3(0, 0.6, -0.8)}) {
          const double radius = isoRadiusAt(f, Vec3(x, 0, 0), dir, r_dev);
          EXPECT_NEAR(radius, rho - r_dev, 0.02 * (rho - r_dev)) << "rho " << rho;
          EXPECT_NEAR(radius, rho - r_dev, 1e-9);  // exact for a straight vessel
        }
      }
    }
  }
}

TEST(VesselField, BulgeAtBifurcationIsMeasured) {
  // Y bifurcation: parent 3.5 mm radius, daughters by Murray's law at +-35 deg.
  const double rp = 3.5e-3, rd = rp / std::cbrt(2.0);
  Centerline c = straightVessel(-0.06, 0.0, 12, rp);
  for (double sign : {1.0, -1.0}) {
    Centerline d = straightVessel(0.0, 0.06, 12, rd);
    const double a = sign * 35.0 * M_PI / 180.0;
    for (auto& p : d.position) p = Vec3(p.x() * std::cos(a), p.x() * std::sin(a), 0.0);
    d.parent[0] = -1;
    c.append(d);
  }
  const VesselField f(c, {}, {}, {});
  // Surface points seen from the centrelines within 3 parent radii of the
  // junction, in all directions; each compared with the radius of the
  // nearest centreline segment.
  auto nearest = [&](const Vec3& p, double* rho) {
    double best = 1e9;
    for (int i = 0; i < c.numPoints(); ++i) {
      if (c.parent[i] < 0) continue;
      const Vec3 a = c.position[c.parent[i]], b = c.position[i];
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      const double dist = (p - a - t * (b - a)).norm();
      if (dist < best) {
        best = dist;
        *rho = c.radius[i];
      }
    }
    return best;
  };
  double bulge = 0.0, waist = 0.0;
  for (int i = 0; i < c.numPoints(); ++i) {
    if (c.position[i].norm() > 3 * rp) continue;
    for (int k = 0; k < 64; ++k) {
      const double th = M_PI * (k + 0.5) / 64, ph = 2.399963 * k;  // spiral directions
      const Vec3 dir(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const SurfacePoint s = firstRoot(f, c.position[i], c.position[i] + 0.02 * dir, 0.0);
      if (!s.hit) continue;
      double rho = rp;
      const double dist = nearest(s.point, &rho);
      bulge = std::max(bulge, dist / rho - 1.0);
      waist = std::max(waist, 1.0 - dist / rho);
    }
  }
  std::printf(
      "[ metric   ] bifurcation (Murray, 70 deg): bulge +%.1f %%, waist -%.1f %% of the "
      "nearest radius\n",
      100.0 * bulge, 100.0 * waist);
  EXPECT_GT(bulge, 0.0);  // the blend widens the junction ...
  EXPECT_LT(bulge, 0.5);  // ... by a bounded amount
  EXPECT_LT(waist, 0.2);
  EXPECT_NEAR(isoRadiusAt(f, Vec3(-0.04, 0, 0), Vec3(0, 0, 1), 0.0), rp, 1e-9);  // far: exact
}

TEST(VesselField, AneurysmChangesTheFieldOnlyInsideItsSupport) {
  const Centerline c = straightVessel(-0.03, 0.03, 12, 2.25e-3);
  const AneurysmSpec dome{Vec3(0.0, 4.5e-3, 0.0), 3.5e-3};
  const VesselField plain(c, {}, {}, {}), sick(c, {dome}, {}, {});
  const double support = dome.radius / sick.alpha();
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-0.012, 0.012);
  int inside_changed = 0, outside = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double a = plain.evaluate(p, 0.0).value, b = sick.evaluate(p, 0.0).value;
    if ((p - dome.center).norm() >= support) {
      EXPECT_EQ(a, b);
      ++outside;
    } else if (a != b) {
      ++inside_changed;
    }
  }
  EXPECT_GT(outside, 1000);
  EXPECT_GT(inside_changed, 100);
  // The dome is open: its centre is inside the lumen.
  EXPECT_GT(sick.evaluate(dome.center, 0.0).value, 0.0);
}

TEST(VesselField, MotionIsPeriodicWithTheDeclaredPeriods) {
  const Centerline c = straightVessel(-0.05, 0.05, 20, 3e-3);
  MotionRegion cardiac{Vec3(0, 0, 0), 0.08, Vec3(0, 1.5e-3, 0), 1.2, 0.0};
  MotionRegion respiratory{Vec3(0.02, 0, 0), 0.2, Vec3(0, 0, 2e-3), 0.25, 0.3};
  for (const auto& region : {cardiac, respiratory}) {
    const VesselField f(c, {}, {region}, {});
    ASSERT_EQ(f.motionPeriods().size(), 1u);
    const double period = f.motionPeriods()[0];
    EXPECT_NEAR(period, 1.0 / region.frequency, 1e-15);
    const Vec3 p(0.01, 2.5e-3, 0.5e-3);
    for (double t : {0.1, 0.37, 1.9}) {
      const double now = f.evaluate(p, 0.0, f.motionAt(t)).value;
      EXPECT_NEAR(f.evaluate(p, 0.0, f.motionAt(t + period)).value, now, 1e-9);
      EXPECT_NEAR(f.evaluate(p, 0.0, f.motionAt(t + 3 * period)).value, now, 1e-9);
    }
    // It does move: a quarter period later the field differs.
    EXPECT_GT(std::abs(f.evaluate(p, 0.0, f.motionAt(0.25 * period)).value -
                       f.evaluate(p, 0.0, f.motionAt(0.75 * period)).value),
              1e-3);
  }
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

TEST(VesselField, MovingVesselsMatchTheirCentrelineMovedAndAtRest) {
  // The field of moving vessels evaluates each segment moved by the
  // snapshot (kept per snapshot): it must equal the field of the centreline
  // whose points were moved by the same displacement, at rest. Snapshots
  // alternate, as a step's and its halves' do.
  Centerline c = straightVessel(-0.05, 0.05, 20, 3e-3);
  c.append(straightVessel(-0.04, 0.04, 12, 2e-3, Vec3(0.0, 0.004, 0.002)));
  const MotionRegion heart{Vec3(0, 0, 0), 0.08, Vec3(0, 1.5e-3, 1e-3), 1.2, 0.0};
  const MotionRegion breath{Vec3(0.02, 0, 0), 0.2, Vec3(0, 0, 2e-3), 0.25, 0.3};
  const VesselField moving(c, {}, {heart, breath}, {});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double t : {0.1, 0.37, 0.1, 1.9, 0.37}) {
    const MotionSnapshot m = moving.motionAt(t);
    Centerline moved = c;
    for (Vec3& x : moved.position) x += moving.displacement(x, m);
    const VesselField at_rest(moved, {}, {}, {});
    for (int k = 0; k < 200; ++k) {
      const Vec3 p(0.04 * u(rng), 0.006 * u(rng), 0.006 * u(rng));
      const FieldSample a = moving.evaluate(p, 1e-4, m), b = at_rest.evaluate(p, 1e-4);
      EXPECT_NEAR(a.value, b.value, 1e-12) << "t " << t << " point " << k;
      EXPECT_LT((a.gradient - b.gradient).norm(), 1e-9 * (1.0 + b.gradient.norm()))
          << "t " << t << " point " << k;
    }
  }
}

}  // namespace
}  // namespace evsim
