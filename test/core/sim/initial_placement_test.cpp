// Devices inserted at the start lie as after an insertion: along the
// vessels' path from the access point where their rest shape would leave
// the lumen, for a device alone, a coaxial pair, at coordinates and at
// `access_point: inlet`; a length that cannot fit is refused at load with
// the length that fits. Independent answers: the vessel field says every
// node lies inside the lumen, and the first steps solve.
#include "endovascular_sim/sim/initial_placement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

std::string sceneText(const std::string& name) {
  std::ifstream in(configDirectory() + "/scenes/" + name + ".yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

SceneModel sceneWith(const std::string& name, const std::string& from, const std::string& to) {
  const std::string text = std::regex_replace(sceneText(name), std::regex(from), to);
  return buildSceneModel(loadSceneText(text, configDirectory() + "/scenes/" + name + ".yaml"));
}

/// Every node past the access point inside the lumen (the field's sign),
/// then `steps` steps solved.
void expectInsideAndSolved(const SceneModel& m, int steps) {
  SimData data = makeData(m);
  for (size_t d = 0; d < m.devices.size(); ++d)
    for (int i = 0; i < m.devices[d].num_nodes; ++i) {
      const DeviceModel& dm = m.devices[d];
      if (dm.node_s[i] < dm.length - data.devices[d].inserted_length) continue;
      EXPECT_GE(m.vessels->evaluate(data.devices[d].position[i], dm.node_radius[i]).value, 0.0)
          << dm.name << " node " << i;
    }
  for (int k = 0; k < steps; ++k) ASSERT_EQ(step(m, &data), StepStatus::kOk) << data.last_error;
}

TEST(InitialPlacement, AWireInsertedAroundTheArchLiesAlongIt) {
  // The catheter and its wire 25 cm from the descending aorta: 13 cm up to
  // the arch, then over it.
  const SceneModel m =
      sceneWith("arch_to_left_subclavian", "inserted_length: [0-9.]+", "inserted_length: 0.25");
  SimData data = makeData(m);
  const std::string tip_vessel = m.atlas->vessels()[data.tips[0].vessel].name;
  EXPECT_TRUE(tip_vessel == "aortic_arch" || tip_vessel == "ascending_aorta") << tip_vessel;
  expectInsideAndSolved(m, 20);
}

TEST(InitialPlacement, ACoaxialPairAtTheInletRuns) {
  // The inlet of carotid.swc is its root, the ascending aorta's end: the
  // pair goes up it, over the arch and down the descending aorta.
  const SceneModel m =
      sceneWith("arch_navigation",
                "access_point: \\[0.025, -0.020, -0.130\\].*\\n.*insertion_direction.*\\n.*up: .*",
                "access_point: inlet");
  expectInsideAndSolved(m, 20);
}

TEST(InitialPlacement, ACoaxialPairAtAPatientsInletRuns) {
  // The VMTK-style centreline, its first segments noisy: straight from the
  // inlet the catheter would leave the lumen.
  std::string text = sceneText("patient_example");
  text = std::regex_replace(
      text, std::regex("devices:[\\s\\S]*?(\\n[a-z])"),
      "effects: [gravity, subdivision, coaxial]\ndevices:\n"
      "  - file: ../devices/catheter.urdf\n    access_point: inlet\n    inserted_length: 0.12\n"
      "  - file: ../devices/guidewire.urdf\n    inside: catheter\n    inserted_length: 0.14\n$1");
  text = std::regex_replace(text, std::regex("\\neffects: \\[gravity, subdivision\\]"), "");
  const SceneModel m =
      buildSceneModel(loadSceneText(text, configDirectory() + "/scenes/patient_example.yaml"));
  ASSERT_EQ(m.devices.size(), 2u);
  expectInsideAndSolved(m, 20);
}

TEST(InitialPlacement, ALengthThatCannotFitIsRefusedWithTheLengthThatFits) {
  try {
    sceneWith("arch_to_left_subclavian", "inserted_length: [0-9.]+", "inserted_length: 0.40");
    FAIL() << "a 40 cm catheter in 29 cm of aorta loaded";
  } catch (const LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("inserted_length"), std::string::npos) << what;
    EXPECT_NE(what.find("at most"), std::string::npos) << what;
    EXPECT_EQ(what.find("inf"), std::string::npos) << what;
  }
}

TEST(InitialPlacement, ThePathFollowsTheCentrelineTheStraightestWay) {
  const SceneModel m = loadScene("arch_navigation");
  const InsertionPath path = insertionPath(*m.centerline, m.introducers[0], 1.0);
  // To a vessel's end: the ascending aorta's root, over the arch.
  EXPECT_EQ(m.centerline->vessel_names[m.centerline->vessel[path.end_point]], "ascending_aorta");
  // On the centreline all along (the access point is on it).
  const Centerline& c = *m.centerline;
  for (double a = 0.0; a < path.length(); a += 0.002) {
    const Vec3 p = path.at(a);
    double nearest = 1e9;
    for (int i = 0; i < c.numPoints(); ++i) {
      if (c.parent[i] < 0) continue;
      const Vec3 q = c.position[c.parent[i]], d = c.position[i] - q;
      const double t = std::clamp((p - q).dot(d) / d.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (q + t * d - p).norm());
    }
    EXPECT_LT(nearest, 1e-9) << a;
  }
}

}  // namespace
}  // namespace evsim
