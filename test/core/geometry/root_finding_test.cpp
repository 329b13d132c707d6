// First roots against a dense-sampling-and-bisection reference.
#include "endovascular_sim/geometry/root_finding.h"

#include <gtest/gtest.h>

#include <random>

#include "endovascular_sim/geometry/vessel_field.h"

namespace evsim {
namespace {

Centerline polyline(const std::vector<Vec3>& points, double rho) {
  Centerline c;
  for (size_t i = 0; i < points.size(); ++i) {
    c.position.push_back(points[i]);
    c.radius.push_back(rho);
    c.parent.push_back(static_cast<int>(i) - 1);
    c.type.push_back(0);
  }
  return c;
}

/// A curved vessel (an arc), a branch, and two parallel vessels whose walls
/// are 40 micrometres apart: a thin wall to cross in one step.
VesselField testVessels() {
  std::vector<Vec3> arc;
  for (int i = 0; i <= 24; ++i) {
    const double a = M_PI * i / 24;
    arc.push_back(Vec3(0.02 * std::cos(a), 0.02 * std::sin(a), 0.0));
  }
  Centerline c = polyline(arc, 3e-3);
  c.append(
      polyline({Vec3(0, 0.02, 0), Vec3(0.003, 0.035, 0.004), Vec3(0.004, 0.05, 0.01)}, 1.5e-3));
  // Two parallel tubes 4.2 mm apart: with a steep kernel (alpha 0.9) their
  // walls stay apart, leaving a thin exterior wall between the lumens.
  c.append(polyline({Vec3(-0.03, -0.01, 0), Vec3(0.03, -0.01, 0)}, 2e-3));
  c.append(polyline({Vec3(-0.03, -0.01, 0.0042), Vec3(0.03, -0.01, 0.0042)}, 2e-3));
  VesselFieldOptions steep;
  steep.alpha = 0.9;
  return VesselField(c, {{Vec3(0.0, 0.0238, 0.0), 2.5e-3}}, {}, steep);
}

/// Reference: the first sign change among dense samples, then bisection.
double referenceRoot(const VesselField& f, const Vec3& p0, const Vec3& p1, double r, bool* hit) {
  const int n = 20000;
  const Vec3 d = p1 - p0;
  double prev = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double s = static_cast<double>(i) / n;
    if (f.evaluate(p0 + s * d, r).value < 0.0) {
      double lo = prev, hi = s;
      for (int k = 0; k < 80; ++k) {
        const double mid = 0.5 * (lo + hi);
        (f.evaluate(p0 + mid * d, r).value >= 0.0 ? lo : hi) = mid;
      }
      *hit = true;
      return hi;
    }
    prev = s;
  }
  *hit = false;
  return 1.0;
}

TEST(FirstRoot, ThinWallStaysOpenInTheTestGeometry) {
  const VesselField f = testVessels();
  EXPECT_LT(f.evaluate(Vec3(0.0, -0.01, 0.0021), 0.0).value, 0.0);  // mid-gap is outside
  // ... and the exterior wall between the lumens is thin (< 0.2 mm).
  const SurfacePoint a = firstRoot(f, Vec3(0, -0.01, 0), Vec3(0, -0.01, 0.0021), 0.0);
  const SurfacePoint b = firstRoot(f, Vec3(0, -0.01, 0.0042), Vec3(0, -0.01, 0.0021), 0.0);
  ASSERT_TRUE(a.hit && b.hit);
  EXPECT_LT(b.point.z() - a.point.z(), 2e-4);
}

TEST(FirstRoot, MatchesDenseBisectionOnRandomSegments) {
  const VesselField f = testVessels();
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, misses = 0, grazing = 0;
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    // Start inside a vessel; move up to 15 mm.
    Vec3 p0;
    do {
      p0 = Vec3(0.03 * u(rng), 0.03 * u(rng) + 0.005, 0.006 * u(rng));
    } while (f.evaluate(p0, 1e-4).value < 0.0);
    const Vec3 p1 = p0 + 0.015 * std::abs(u(rng)) * Vec3(u(rng), u(rng), u(rng)).normalized();
    bool ref_hit;
    const double ref = referenceRoot(f, p0, p1, 1e-4, &ref_hit);
    const SurfacePoint got = firstRoot(f, p0, p1, 1e-4);
    ASSERT_EQ(got.hit, ref_hit) << "segment " << k;
    if (!ref_hit) {
      ++misses;
      continue;
    }
    ++hits;
    const double err = std::abs(got.s - ref) * (p1 - p0).norm();
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-9) << "segment " << k;
    if (std::abs(got.normal.dot((p1 - p0).normalized())) < 0.1) ++grazing;
  }
  // Grazing batch: chords that meet the straight tube's wall at shallow
  // angles (1e-4 ... 0.1 rad), and short steps along the wall.
  for (int k = 0; k < 1000; ++k) {
    const double angle = std::pow(10.0, -4.0 + 3.0 * std::abs(u(rng)));
    const double depth = 2e-3 - 1e-4 - 1e-6 * std::abs(u(rng));  // start 0.1 mm inside
    const double phi = M_PI * u(rng);
    const Vec3 radial(0.0, std::cos(phi), std::sin(phi));
    const Vec3 p0 = Vec3(0.01 * u(rng), -0.01, 0.0) + depth * radial;
    const Vec3 dir = (Vec3(1, 0, 0) + std::tan(angle) * radial).normalized();
    const Vec3 p1 = p0 + 0.015 * dir;
    bool ref_hit;
    const double ref = referenceRoot(f, p0, p1, 0.0, &ref_hit);
    const SurfacePoint got = firstRoot(f, p0, p1, 0.0);
    ASSERT_EQ(got.hit, ref_hit) << "grazing segment " << k;
    if (!ref_hit) continue;
    ++grazing;
    const double err = std::abs(got.s - ref) * 0.015;
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-9) << "grazing segment " << k;
  }
  std::printf("[ metric   ] first root: %d hits, %d grazing hits, %d misses, worst error %.2e m\n",
              hits, grazing, misses, worst);
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 500);
  EXPECT_GT(grazing, 200);
}

TEST(FirstRoot, CertifiedFromBothEndsTheSameAsFromTheStart) {
  // firstRootBetween also certifies the path backwards from its end and by
  // the chord bound: the same hits (to the bit: the same forward search
  // finds them) on random, short and grazing paths, in fewer evaluations.
  const VesselField f = testVessels();
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, misses = 0;
  for (int k = 0; k < 4000; ++k) {
    Vec3 p0;
    do {
      p0 = Vec3(0.03 * u(rng), 0.03 * u(rng) + 0.005, 0.006 * u(rng));
    } while (f.evaluate(p0, 1e-4).value < 0.0);
    const double length = std::pow(10.0, -6.0 + 4.5 * std::abs(u(rng)));  // 1 um .. 30 mm
    const Vec3 p1 = p0 + length * Vec3(u(rng), u(rng), u(rng)).normalized();
    const FieldSample g0 = f.evaluate(p0, 1e-4), g1 = f.evaluate(p1, 1e-4);
    const SurfacePoint from = firstRootFrom(f, p0, g0, p1, 1e-4);
    const SurfacePoint between = firstRootBetween(f, p0, g0, p1, g1, 1e-4);
    ASSERT_EQ(between.hit, from.hit) << "path " << k;
    (from.hit ? hits : misses) += 1;
    if (!from.hit) continue;
    EXPECT_EQ(between.s, from.s) << "path " << k;
    EXPECT_EQ(between.point, from.point) << "path " << k;
  }
  EXPECT_GT(hits, 300);
  EXPECT_GT(misses, 1000);
}

TEST(FirstRoot, ACrossingOfAThinWallInOneStepIsCaught) {
  const VesselField f = testVessels();
  // From the centre of one parallel tube straight into the other: the wall
  // pair and the 40 um gap lie between.
  const Vec3 p0(0.001, -0.01, 0.0), p1(0.001, -0.01, 0.0042);
  ASSERT_GT(f.evaluate(p1, 0.0).value, 0.0);  // the end is inside the other vessel
  const SurfacePoint s = firstRoot(f, p0, p1, 0.0);
  ASSERT_TRUE(s.hit);
  EXPECT_LT(s.point.z(), 0.0021);  // the first wall, not the second
  EXPECT_LT(s.normal.z(), -0.9);   // its normal points back into the first lumen
}

TEST(FirstRoot, GrazingSegmentThatStaysInsideIsNotAHit) {
  const Centerline c = polyline({Vec3(-0.1, 0, 0), Vec3(0.1, 0, 0)}, 2e-3);
  const VesselField f(c, {}, {}, {});
  // Sliding 0.1 mm (a fast step) along the wall, 10 nm inside: no hit, in
  // few certified steps (about 2 um each at the default 1 nm tolerance).
  const double y = 2e-3 - 1e-8;
  const SurfacePoint slide = firstRoot(f, Vec3(0.0, y, 0), Vec3(1e-4, y, 0), 0.0);
  EXPECT_FALSE(slide.hit);
  EXPECT_LT(slide.iterations, 200);
  // Sliding on the wall itself with a 1e-7 m crossing depth: a 20 um step
  // is certified in a handful of iterations.
  RootOptions contact;
  contact.crossing_depth = 1e-7;
  const SurfacePoint on =
      firstRoot(f, Vec3(0.0, 2e-3 - 1e-13, 0), Vec3(2e-5, 2e-3 - 1e-13, 0), 0.0, {}, contact);
  EXPECT_FALSE(on.hit);
  EXPECT_LT(on.iterations, 10);
}

TEST(ProjectToSurface, ReachesTheWallAlongTheGradient) {
  const Centerline c = polyline({Vec3(-0.1, 0, 0), Vec3(0.1, 0, 0)}, 2e-3);
  const VesselField f(c, {}, {}, {});
  for (double y : {1.5e-3, 2.3e-3}) {  // inside and outside the wall
    const SurfacePoint s = projectToSurface(f, Vec3(0.004, y * 0.6, y * 0.8), 0.0);
    ASSERT_TRUE(s.hit);
    EXPECT_NEAR(s.point.tail<2>().norm(), 2e-3, 1e-10);
    EXPECT_NEAR(s.point.x(), 0.004, 1e-12);
    EXPECT_LT((s.normal + Vec3(0, 0.6, 0.8)).norm(), 1e-9);  // into the lumen
  }
}

/// The test vessels, counting the field's evaluations.
class CountingField : public ImplicitSurface {
 public:
  explicit CountingField(const VesselField& f) : f_(f) {}
  FieldSample evaluate(const Vec3& p, double r, const MotionSnapshot& m = {}) const override {
    ++evaluations;
    return f_.evaluate(p, r, m);
  }
  double hessianBound(const Vec3& p0, const Vec3& p1, double r) const override {
    return f_.hessianBound(p0, p1, r);
  }
  mutable long evaluations{0};

 private:
  const VesselField& f_;
};

TEST(ProjectToSurface, FromNearTheWallTheFirstRootAlongTheGradientInAFewEvaluations) {
  // Points from 0.1 nm to 0.1 mm off the wall, on both sides (a kept
  // contact's point, a point beyond the wall to update): the projection
  // agrees with dense sampling and bisection along its line, and costs
  // about two evaluations where the certified steps and the bracketing took
  // five or six.
  const VesselField f = testVessels();
  const CountingField counted(f);
  const double r = 1e-4, reach = 0.01;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int points = 0, near_points = 0;
  double worst = 0.0;
  long evaluations = 0, near_evaluations = 0;  // near: within 1 um
  while (points < 300) {
    Vec3 p0;
    do {
      p0 = Vec3(0.03 * u(rng), 0.03 * u(rng) + 0.005, 0.006 * u(rng));
    } while (f.evaluate(p0, r).value < 0.0);
    const Vec3 p1 = p0 + 0.015 * Vec3(u(rng), u(rng), u(rng)).normalized();
    const SurfacePoint wall = firstRoot(f, p0, p1, r);
    if (!wall.hit) continue;
    const double off = std::pow(10.0, -10.0 + 6.0 * std::abs(u(rng))) * (u(rng) < 0 ? -1 : 1);
    const Vec3 x = wall.point + off * wall.normal;
    const FieldSample at = f.evaluate(x, r);
    if (at.gradient.norm() == 0.0) continue;
    // Reference: the first change of sign along the gradient's line, by
    // dense samples (5 um apart) and bisection.
    const double sigma = at.value >= 0.0 ? 1.0 : -1.0;
    const Vec3 toward = -sigma * at.gradient.normalized();
    const int n = 2000;
    double lo = 0.0, hi = -1.0;
    for (int i = 1; i <= n && hi < 0.0; ++i) {
      const double t = reach * i / n;
      if (sigma * f.evaluate(x + t * toward, r).value < 0.0)
        hi = t;
      else
        lo = t;
    }
    const long before = counted.evaluations;
    const SurfacePoint got = projectToSurfaceFrom(counted, x, at, r, {}, reach);
    evaluations += counted.evaluations - before;
    if (std::abs(off) <= 1e-6) {
      near_evaluations += counted.evaluations - before;
      ++near_points;
    }
    ASSERT_EQ(got.hit, hi >= 0.0) << "point " << points;
    if (!got.hit) continue;
    for (int k = 0; k < 80; ++k) {
      const double mid = 0.5 * (lo + hi);
      (sigma * f.evaluate(x + mid * toward, r).value >= 0.0 ? lo : hi) = mid;
    }
    const double err = (got.point - (x + hi * toward)).norm();
    worst = std::max(worst, err);
    EXPECT_LT(err, 2e-11) << "point " << points << " at " << off << " m";
    EXPECT_LT(sigma * f.evaluate(got.point, r).value, 0.0) << "on the other side";
    EXPECT_LT((got.normal - f.evaluate(got.point, r).gradient.normalized()).norm(), 1e-12);
    ++points;
  }
  const double mean = static_cast<double>(evaluations) / points;
  const double near_mean = static_cast<double>(near_evaluations) / near_points;
  std::printf(
      "[ metric   ] projection from 0.1 nm - 0.1 mm: %d points, worst %.2e m, "
      "%.2f evaluations each, %.2f within 1 um\n",
      points, worst, mean, near_mean);
  EXPECT_LT(near_mean, 3.0);
  EXPECT_LT(mean, 4.5);
}

}  // namespace
}  // namespace evsim
