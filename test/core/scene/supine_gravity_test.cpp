// Gravity for a patient on the table: `gravity: supine` pulls toward the
// patient's posterior in the frame the vessel file declares. A wire at
// rest in a horizontal straight tube must lie on the posterior wall: its
// free length, cantilevered from the introducer at the tube's axis, sags
// until it lies along the wall at y = -(R - r) (R the lumen radius, r the
// wire's), whichever axis the frame calls posterior.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/patient_frame.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "wire_urdf.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

constexpr double kLumen = 0.004;     // [m] the tube's radius
constexpr double kWire = 0.000178;   // [m] the wire's radius
constexpr double kTubeLength = 0.2;  // [m] along x, horizontal
constexpr double kInserted = 0.16;   // [m] of wire in the tube


/// A folder with the tube (its SWC declaring `frame`), the wire and a scene
/// with `gravity` as given.
class SupineGravity : public ::testing::Test {
 protected:
  void write(const std::string& frame, const std::string& gravity,
             const std::string& vessels_extra = "") {
    dir_ = fs::temp_directory_path() / ("evsim_supine_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "wire.urdf") << test::wireUrdf(0.0002, kWire, 0.3, 6e9, 60);
    std::ofstream swc(dir_ / "tube.swc");
    swc << "# units: mm\n";
    if (!frame.empty()) swc << "# frame: " << frame << "\n";
    for (int i = 0; i <= 40; ++i)
      swc << i + 1 << " 1 " << i * kTubeLength * 1e3 / 40 << " 0 0 " << kLumen * 1e3 << " "
          << (i == 0 ? -1 : i) << "\n";
    swc.close();
    std::ofstream(dir_ / "scene.yaml")
        << "name: tube\ntime_step: 0.001\neffects: [gravity]\n"
        << (gravity.empty() ? "" : "gravity: " + gravity + "\n")
        << "vessels:\n  centerline: tube.swc\n"
        << vessels_extra << "devices:\n  - file: wire.urdf\n    access_point: [0.01, 0, 0]\n"
        << "    insertion_direction: [1, 0, 0]\n    inserted_length: " << kInserted << "\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// The scene stepped `seconds`; the mean offset [m] from the tube's axis of
  /// the wire's nodes over the distal third of its free length.
  Vec3 restingOffset(const SceneModel& m, double seconds) {
    SimData data = makeData(m);
    while (data.time < seconds) EXPECT_EQ(step(m, &data), StepStatus::kOk) << data.last_error;
    const std::vector<Vec3>& x = data.devices[0].position;
    Vec3 sum = Vec3::Zero();
    int n = 0;
    for (const Vec3& p : x)
      if (p.x() > 0.01 + 0.75 * kInserted && p.x() < 0.01 + 0.95 * kInserted) sum += p, ++n;
    EXPECT_GT(n, 5);
    return Vec3(0.0, sum.y(), sum.z()) / std::max(n, 1);
  }
  fs::path dir_;
};

TEST_F(SupineGravity, AWireAtRestLiesOnThePosteriorWall) {
  // LAS: y anterior, so posterior is -y; LPS: +y.
  for (const std::string frame : {"LAS", "LPS", "LSA"}) {
    write(frame, "supine");
    const SceneModel m = loadScene((dir_ / "scene.yaml").string());
    const Vec3 posterior = posteriorDirection(frame);
    EXPECT_NEAR((m.gravity - 9.81 * posterior).norm(), 0.0, 1e-12) << frame;
    const Vec3 offset = restingOffset(m, 1.5);
    // On the wall (within the surface's fidelity and the contact tolerance):
    // the sag alone, unsupported, would reach 0.1 m.
    EXPECT_NEAR(offset.dot(posterior), kLumen - kWire, 0.15e-3) << frame;
    EXPECT_NEAR((offset - offset.dot(posterior) * posterior).norm(), 0.0, 0.05e-3) << frame;
  }
}

TEST_F(SupineGravity, ProneLiesOnTheAnteriorWallAndUnsetMeansSupine) {
  write("LAS", "prone");
  EXPECT_NEAR(restingOffset(loadScene((dir_ / "scene.yaml").string()), 1.5).y(), kLumen - kWire,
              0.15e-3);
  write("LAS", "");
  EXPECT_NEAR((loadScene((dir_ / "scene.yaml").string()).gravity - Vec3(0, -9.81, 0)).norm(), 0.0,
              1e-12);
}

TEST_F(SupineGravity, NeedsAFrameAndRefusesAContradiction) {
  write("", "supine");
  try {
    loadScene((dir_ / "scene.yaml").string());
    ADD_FAILURE() << "supine without a frame loaded";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("vessels.frame"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 4) << e.what();  // the gravity key's line
  }
  write("", "supine", "  frame: LAS\n");  // the scene declares it
  EXPECT_NEAR(loadScene((dir_ / "scene.yaml").string()).gravity.y(), -9.81, 1e-12);
  write("LPS", "supine", "  frame: LAS\n");
  EXPECT_THROW(loadScene((dir_ / "scene.yaml").string()), LoadError);
  write("LAS", "supine", "  frame: LAX\n");
  EXPECT_THROW(loadScene((dir_ / "scene.yaml").string()), LoadError);
  // A vector off the posterior axis with the frame known: a warning.
  write("LAS", "[0, 0, -9.81]");
  const SceneModel m = loadScene((dir_ / "scene.yaml").string());
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("posterior"), std::string::npos) << m.warnings[0];
  write("LAS", "[0, 0, -1e20]");
  EXPECT_THROW(loadScene((dir_ / "scene.yaml").string()), LoadError);
}

TEST(PatientFrame, CodesAndDirections) {
  EXPECT_EQ(frameCodeProblem("RAS"), "");
  EXPECT_NE(frameCodeProblem("ISP"), "");  // two of S/I
  EXPECT_NE(frameCodeProblem("RLS"), "");
  EXPECT_NE(frameCodeProblem("RA"), "");
  EXPECT_EQ(posteriorDirection("RAS"), Vec3(0, -1, 0));
  EXPECT_EQ(posteriorDirection("LPS"), Vec3(0, 1, 0));
  EXPECT_EQ(posteriorDirection("PIR"), Vec3(1, 0, 0));
  EXPECT_EQ(superiorDirection("PIR"), Vec3(0, -1, 0));
}

}  // namespace
}  // namespace evsim
