// The effect 'vessel_deformation' in a running simulation: a heavy wire
// lying in a long horizontal tube presses its floor down. At rest the
// tube's skeleton must take the shape that Hetenyi's beam on an elastic
// foundation gives for the contact forces the simulation reports (each a
// point load on an infinite beam, superposed), and the wire must lie on the
// moved wall. With the effect off, the same scene with the same `wall`
// section steps bit for bit as without it, and the wall's code never runs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/sim/simulation.h"
#include "wire_urdf.h"
#include "endovascular_sim/sim/state_file.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

constexpr double kLumen = 0.004;  // [m] the tube's radius
constexpr double kWire = 0.000445;
constexpr double kTubeStart = -0.2, kTubeEnd = 0.4;  // [m] along x, horizontal
constexpr int kTubeSegments = 240;                   // 2.5 mm each
constexpr double kInserted = 0.12;                   // [m] of wire in the tube
constexpr double kGravity = 500.0;                   // [m/s^2], downward (-z)
constexpr double kTether = 2000.0, kDamping = 20.0;  // [N/m^2], [N s/m^2]
constexpr double kDistensibility = 1.2e-5;           // [1/Pa]


class VesselDeformation : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("evsim_wall_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "wire.urdf") << test::wireUrdf(0.0012, kWire, 0.2, 4e9, 50);
    std::ofstream swc(dir_ / "tube.swc");
    swc << "# units: mm\n# vessel: tube 1\n";
    for (int i = 0; i <= kTubeSegments; ++i)
      swc << i + 1 << " 1 " << 1e3 * (kTubeStart + i * (kTubeEnd - kTubeStart) / kTubeSegments)
          << " 0 0 " << kLumen * 1e3 << " " << (i == 0 ? -1 : i) << "\n";
  }
  void write(const std::string& effects, const std::string& wall, double gravity = kGravity) {
    std::ofstream(dir_ / "scene.yaml")
        << "name: tube\ntime_step: 0.001\neffects: [gravity, subdivision" << effects << "]\n"
        << "gravity: [0, 0, " << -gravity << "]\n"
        << "vessels:\n  centerline: tube.swc\n"
        << wall << "devices:\n  - file: wire.urdf\n    access_point: [0, 0, 0]\n"
        << "    insertion_direction: [1, 0, 0]\n    inserted_length: " << kInserted << "\n";
  }
  std::string wallSection() const {
    std::ostringstream s;
    s << "  wall:\n    distensibility: " << kDistensibility << "\n    tether_stiffness: " << kTether
      << "\n    tether_damping: " << kDamping << "\n";
    return s.str();
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string scene() const { return (dir_ / "scene.yaml").string(); }
  fs::path dir_;
};

TEST_F(VesselDeformation, TheTubeTakesHetenyisShapeUnderTheContactForces) {
  write(", vessel_deformation", wallSection());
  const SceneModel m = loadScene(scene());
  ASSERT_TRUE(m.wall);
  SimData data = makeData(m);
  while (data.time < 1.5) ASSERT_EQ(step(m, &data), StepStatus::kOk) << data.last_error;
  ASSERT_TRUE(data.wall);
  const double ei = 2 * M_PI * std::pow(kLumen, 4) / kDistensibility;  // thin tube: pi R^3 E h
  const double beta = std::pow(kTether / (4 * ei), 0.25);              // [1/m]
  // Every wall contact a point load; the floor's deflection at each
  // centreline point their superposition on an infinite beam.
  double total = 0.0, worst = 0.0, peak = 0.0, most_penetrated = 0.0;
  for (const Contact& c : data.contacts) {
    if (c.other_device >= 0 || c.lumen) continue;
    total += c.force * c.normal.z();
    most_penetrated = std::min(most_penetrated, c.gap);
  }
  const double weight = kGravity * 0.0012 * kInserted / 0.2;  // of the wire in the tube [N]
  // (the introducer holds the wire's proximal end: the floor carries the rest)
  EXPECT_GT(total, 0.5 * weight);
  EXPECT_LT(total, weight);
  // The sheath holds the tube within 5 mm of the access point (x = 0): the
  // infinite beam holds from three decay lengths beyond that.
  const Centerline& c = *m.centerline;
  int compared = 0;
  for (int i = 0; i < c.numPoints(); ++i) {
    if (c.position[i].x() < 5e-3 + 3 / beta) continue;
    ++compared;
    double w = 0.0;
    for (const Contact& k : data.contacts) {
      if (k.other_device >= 0 || k.lumen) continue;
      const double x = beta * std::abs(c.position[i].x() - k.point.x());
      w -= k.force * k.normal.z() * beta / (2 * kTether) * std::exp(-x) *
           (std::cos(x) + std::sin(x));
    }
    peak = std::max(peak, std::abs(w));
    worst = std::max(worst, std::abs(data.wall->displacement[i].z() - w));
    EXPECT_LT(std::abs(data.wall->displacement[i].y()), 1e-9) << i;
  }
  std::printf("floor load %.4f N of the wire's %.4f N; deepest %.3f mm; worst %.4f mm\n", total,
              weight, peak * 1e3, worst * 1e3);
  EXPECT_GT(compared, 100);
  EXPECT_GT(peak, 1e-3) << "the floor moved by a millimetre or more";
  EXPECT_LT(worst, 0.015 * peak) << "worst " << worst << " m of the deepest " << peak << " m";
  // The wire lies on the moved floor, within the contact tolerance.
  EXPECT_GT(most_penetrated, -m.contact.penetration_tolerance - 1e-9);
  const std::vector<Vec3>& x = data.devices[0].position;
  const int tip = static_cast<int>(x.size()) - 1;
  int a = 0, b = 0;
  double t = 0.0;
  MotionSnapshot now;
  now.wall = data.wall;
  ASSERT_TRUE(m.vessels->nearestSegment(x[tip], now, &a, &b, &t));
  const double floor =
      (1 - t) * data.wall->displacement[a].z() + t * data.wall->displacement[b].z();
  EXPECT_NEAR(x[tip].z(), floor - (kLumen - kWire), 0.15e-3);
  EXPECT_GT(data.effect_calls.vessel_deformation, 1000);
}

TEST_F(VesselDeformation, AResumedRunAndACopyStepAsTheUninterruptedOne) {
  write(", vessel_deformation", wallSection());
  const SceneModel m = loadScene(scene());
  SimData run = makeData(m);
  for (int s = 0; s < 200; ++s) ASSERT_EQ(step(m, &run), StepStatus::kOk) << run.last_error;
  const std::string saved = stateText(m, run);
  SimData resumed = makeData(m);
  loadStateText(m, saved, "saved", &resumed);
  SimData copy = run;
  ASSERT_TRUE(resumed.wall);
  for (int s = 0; s < 200; ++s) {
    ASSERT_EQ(step(m, &run), StepStatus::kOk);
    ASSERT_EQ(step(m, &resumed), StepStatus::kOk);
    ASSERT_EQ(step(m, &copy), StepStatus::kOk);
  }
  for (size_t n = 0; n < run.devices[0].position.size(); ++n) {
    ASSERT_EQ(run.devices[0].position[n], resumed.devices[0].position[n]) << n;
    ASSERT_EQ(run.devices[0].position[n], copy.devices[0].position[n]) << n;
  }
  for (size_t i = 0; i < run.wall->displacement.size(); ++i)
    ASSERT_EQ(run.wall->displacement[i], resumed.wall->displacement[i]) << i;
  // A wall beyond the scene's reach is refused, the data unchanged.
  std::string bad = saved;
  const size_t at = bad.find("wall_point ");
  ASSERT_NE(at, std::string::npos);
  bad.replace(at, 11, "wall_point 1 ");
  EXPECT_THROW(loadStateText(m, bad, "bad", &resumed), LoadError);
}

TEST_F(VesselDeformation, OffItCostsNothingAndChangesNoBit) {
  write("", "", 9.81);
  const SceneModel plain = loadScene(scene());
  write("", wallSection(), 9.81);
  const SceneModel with_section = loadScene(scene());
  EXPECT_FALSE(with_section.wall);
  SimData a = makeData(plain), b = makeData(with_section);
  for (int s = 0; s < 300; ++s) {
    ASSERT_EQ(step(plain, &a), StepStatus::kOk) << s << " " << a.last_error;
    ASSERT_EQ(step(with_section, &b), StepStatus::kOk);
  }
  EXPECT_FALSE(a.contacts.empty());
  for (size_t n = 0; n < a.devices[0].position.size(); ++n)
    ASSERT_EQ(a.devices[0].position[n], b.devices[0].position[n]) << n;
  EXPECT_EQ(b.effect_calls.vessel_deformation, 0);
  EXPECT_FALSE(b.wall);
}

TEST_F(VesselDeformation, BadWallsAreRefusedWithTheKeyAndLine) {
  const auto refusal = [&](const std::string& wall) -> std::string {
    write(", vessel_deformation", wall);
    try {
      loadScene(scene());
    } catch (const LoadError& e) {
      return std::to_string(e.line()) + " " + e.what();
    }
    return "loaded";
  };
  EXPECT_EQ(refusal("  wall:\n    tether_stiffness: -5\n").substr(0, 2), "8 ");
  EXPECT_NE(refusal("  wall:\n    tether_stiffness: -5\n").find("vessels.wall.tether_stiffness"),
            std::string::npos);
  EXPECT_NE(refusal("  wall:\n    distensibility: 0\n").find("vessels.wall.distensibility"),
            std::string::npos);
  const std::string unknown = refusal("  wall:\n    vessels:\n      - name: aorta\n");
  EXPECT_NE(unknown.find("no vessel 'aorta' (the vessels: tube)"), std::string::npos) << unknown;
  EXPECT_EQ(unknown.substr(0, 2), "9 ") << unknown;
  EXPECT_NE(refusal("  wall:\n    reach: 1\n").find("vessels.wall.reach"), std::string::npos);
}

}  // namespace
}  // namespace evsim
