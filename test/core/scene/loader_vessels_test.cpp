// Scene files with vessels: targets, VTK centrelines and their keys, the
// inlet access, warnings about a suspect tree, sleep options; each bad input
// gives an error that names the file, the line and the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "loader_fixture.h"

namespace evsim {
namespace {

using test::expectNames;
using test::kDevice;
using test::kScene;
using test::Loader;
namespace fs = std::filesystem;

TEST_F(Loader, ATargetMustNameAVesselOfTheScene) {
  std::string text = carotidScene("[0.025, -0.02, -0.13]");
  text += "targets:\n  - left_subclavian\n  - {vessel: left_comon_carotid, device: wire}\n";
  const SceneSpec spec = loadSceneFile(write("scene.yaml", text));
  ASSERT_EQ(spec.targets.size(), 2u);
  try {
    buildSceneModel(spec);
    ADD_FAILURE() << "accepted";
  } catch (const LoadError& e) {
    EXPECT_EQ(e.line(), 15) << e.what();
    EXPECT_EQ(e.field(), "targets[1]");
    EXPECT_NE(std::string(e.what()).find("nearest: left_common_carotid"), std::string::npos)
        << e.what();
  }
  // A depth out of range, or an unknown device, is refused at load.
  std::string deep = text;
  deep.replace(deep.find("device: wire}"), 13, "device: wire, depth: 5}");
  EXPECT_THROW(loadSceneFile(write("deep.yaml", deep)), LoadError);
  std::string other = text;
  other.replace(other.find("device: wire}"), 13, "device: coil}");
  EXPECT_THROW(loadSceneFile(write("other.yaml", other)), LoadError);
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

/// kScene on the shipped patient example (a VTK centreline), `vessels` as given.
std::string vtkScene(const std::string& vessels) {
  std::string text = kScene;
  text.replace(text.find("devices:"), 8, "vessels: " + vessels + "\ndevices:");
  return text;
}

TEST_F(Loader, AVtkCentrelineNeedsItsUnitsDeclared) {
  write("wire.urdf", kDevice);
  const std::string file = configDirectory() + "/vessels/example_patient.vtp";
  const LoadError e = errorFor(vtkScene("{centerline: " + file + "}"), "scene.yaml", "", "",
                               [](const std::string& p) { loadSceneFile(p); });
  expectNames(e, "scene.yaml", 5, "vessels.units", "SimVascular models are in cm");
}

TEST_F(Loader, VtkKeysAreRefusedForAnSwcCentreline) {
  write("wire.urdf", kDevice);
  const std::string file = configDirectory() + "/vessels/carotid.swc";
  const LoadError e =
      errorFor(vtkScene("{centerline: " + file + ", radius_array: Radius}"), "scene.yaml", "", "",
               [](const std::string& p) { loadSceneFile(p); });
  expectNames(e, "scene.yaml", 5, "vessels.radius_array", "applies to a VTK centreline");
}

TEST_F(Loader, AMissingRadiusArrayListsTheArraysPresent) {
  write("wire.urdf", kDevice);
  const std::string file = configDirectory() + "/vessels/example_patient.vtp";
  const std::string path =
      write("scene.yaml", vtkScene("{centerline: " + file + ", units: mm, radius_array: Radius}"));
  try {
    buildSceneModel(loadSceneFile(path));
    ADD_FAILURE() << "accepted";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("no point-data array 'Radius'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("its point arrays: MaximumInscribedSphereRadius"),
              std::string::npos)
        << e.what();
    EXPECT_EQ(e.file(), file);
  }
}

TEST_F(Loader, BranchNamesMustBeVesselNamesOnce) {
  write("wire.urdf", kDevice);
  const std::string v = "{centerline: " + configDirectory() +
                        "/vessels/example_patient.vtp, units: mm, names: {0: aorta, 1: ";
  auto fails = [&](const std::string& second, const std::string& words) {
    const LoadError e = errorFor(vtkScene(v + second + "}}"), "scene.yaml", "", "",
                                 [](const std::string& p) { loadSceneFile(p); });
    EXPECT_EQ(e.field(), "vessels.names.1") << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  };
  fails("Aorta", "not a vessel name");
  // One name for two branches is a chain, checked with the tree: 0 and 1
  // are no chain.
  const LoadError chain = errorFor(vtkScene(v + "aorta}}"), "scene.yaml", "", "",
                                   [](const std::string& p) { loadScene(p); });
  EXPECT_NE(std::string(chain.what()).find("do not follow one another"), std::string::npos)
      << chain.what();
}

TEST_F(Loader, InletAccessNeedsVesselsAndTakesNoDirection) {
  const LoadError none = sceneError("access_point: [0, 0, 0]\n    insertion_direction: [1, 0, 0]",
                                    "access_point: inlet");
  expectNames(none, "scene.yaml", 7, "devices[0].access_point", "inlet needs vessels");
  const LoadError direction = errorFor(carotidScene("inlet"), "scene.yaml", "", "",
                                       [](const std::string& p) { loadSceneFile(p); });
  expectNames(direction, "scene.yaml", 9, "devices[0].insertion_direction",
              "follows the centreline");
}

TEST_F(Loader, AWireAimedAcrossItsVesselIsWarnedAndANetworkThatCannotGrowRefused) {
  // The carotid tree's descending aorta runs along z: entering along x, the
  // wire meets the wall 12 mm ahead.
  std::string text = carotidScene("[0.025, -0.020, -0.130]");
  auto warned = [](const SceneModel& m, const std::string& words) {
    return std::any_of(m.warnings.begin(), m.warnings.end(),
                       [&](const std::string& w) { return w.find(words) != std::string::npos; });
  };
  const SceneModel across = buildSceneModel(loadSceneFile(write("across.yaml", text)));
  EXPECT_EQ(across.warnings.size(), 1u);
  EXPECT_TRUE(warned(across, "devices[0] (wire) enters at 90 degrees"));
  text.replace(text.find("insertion_direction: [1, 0, 0]"), 30, "insertion_direction: [0, 0, 1]");
  EXPECT_FALSE(warned(buildSceneModel(loadSceneFile(write("along.yaml", text))), "enters at"));
  // Every leaf of the tree is narrower than min_radius: no vessel grows.
  const std::string swc = configDirectory() + "/vessels/carotid.swc";
  text.replace(
      text.find("vessels: {centerline: " + swc + "}"), swc.size() + 23,
      "vessels: {centerline: " + swc + ", network: {seed: 1, vessels: 10, min_radius: 0.05}}");
  const int line =
      1 + static_cast<int>(std::count(text.begin(), text.begin() + text.find("vessels: {"), '\n'));
  const LoadError none = errorFor(text, "network.yaml", "", "",
                                  [](const std::string& p) { buildSceneModel(loadSceneFile(p)); });
  expectNames(none, "network.yaml", line, "vessels.network.vessels", "only 0 of the 10 vessels");
}

TEST_F(Loader, SleepOptionsAreChecked) {
  const LoadError word = sceneError("devices:", "sleep: maybe\ndevices:");
  expectNames(word, "scene.yaml", 5, "sleep", "true, false or a map");
  const LoadError range = sceneError("devices:", "sleep: {displacement: -1}\ndevices:");
  expectNames(range, "scene.yaml", 5, "sleep.displacement", "must lie in (0, 1e-4] m, got -1");
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("devices:"), 8, "sleep: false\ndevices:");
  EXPECT_FALSE(loadSceneFile(write("off.yaml", text)).sleep.enabled);
}

}  // namespace
}  // namespace evsim
