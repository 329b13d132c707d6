// Device and scene files: shipped ones load; each kind of bad input gives an
// error that names the file, the line and the field, and nothing crashes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

const char* kDevice = R"(<?xml version="1.0"?>
<robot name="wire">
  <link name="shaft">
    <inertial><mass value="0.0002"/>
      <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-12"/></inertial>
    <collision><geometry><cylinder radius="0.000178" length="0.3"/></geometry></collision>
  </link>
  <link name="tip">
    <inertial><mass value="0.00001"/>
      <inertia ixx="1e-9" ixy="0" ixz="0" iyy="1e-9" iyz="0" izz="1e-13"/></inertial>
    <collision><geometry><cylinder radius="0.000178" length="0.02"/></geometry></collision>
  </link>
  <joint name="j" type="fixed"><parent link="shaft"/><child link="tip"/></joint>
  <evsim_device max_insertion_speed="0.05" max_rotation_speed="6.28"/>
  <evsim_section link="shaft" young_modulus="6e10" poisson_ratio="0.33" elements="30"/>
  <evsim_section link="tip" young_modulus="2e10" poisson_ratio="0.33" elements="10"
                 rest_curvature="0 0 100"/>
</robot>
)";

const char* kScene = R"(name: test
time_step: 0.001
effects: [gravity]
gravity: [0, 0, -9.81]
devices:
  - file: wire.urdf
    access_point: [0, 0, 0]
    insertion_direction: [1, 0, 0]
    inserted_length: 0.05
script:
  - {time: 0.5, device: wire, insertion: 0.01}
)";

class Loader : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("evsim_loader_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  /// kScene in the carotid tree's vessels, its wire entering at `access`
  /// (written as wire.urdf).
  std::string carotidScene(const std::string& access) {
    write("wire.urdf", kDevice);
    std::string text = kScene;
    text.replace(text.find("devices:"), 8,
                 "vessels: {centerline: " + configDirectory() + "/vessels/carotid.swc}\ndevices:");
    text.replace(text.find("access_point: [0, 0, 0]"), 23, "access_point: " + access);
    return text;
  }

  /// Writes `text` with `from` replaced by `to` as `name`, loads it with
  /// `load`, returns the error.
  template <typename Load>
  LoadError errorFor(std::string text, const std::string& name, const std::string& from,
                     const std::string& to, Load load) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const std::string path = write(name, text);
    try {
      load(path);
    } catch (const LoadError& e) {
      return e;
    }
    ADD_FAILURE() << "no error for " << to;
    return LoadError("", 0, "", "");
  }

  LoadError deviceError(const std::string& from, const std::string& to) {
    return errorFor(kDevice, "wire.urdf", from, to,
                    [](const std::string& p) { loadDeviceFile(p); });
  }

  LoadError sceneError(const std::string& from, const std::string& to) {
    write("wire.urdf", kDevice);
    return errorFor(kScene, "scene.yaml", from, to, [](const std::string& p) { loadSceneFile(p); });
  }

  fs::path dir_;
};

void expectNames(const LoadError& e, const std::string& file, int line, const std::string& field,
                 const std::string& words) {
  EXPECT_EQ(fs::path(e.file()).filename().string(), file) << e.what();
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.field(), field) << e.what();
  EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find(file + ":" + std::to_string(line)), std::string::npos)
      << e.what();
}

TEST_F(Loader, ValidDeviceAndSceneLoad) {
  write("wire.urdf", kDevice);
  const SceneSpec s = loadSceneFile(write("scene.yaml", kScene));
  ASSERT_EQ(s.devices.size(), 1u);
  const DeviceSpec& d = s.devices[0].device;
  EXPECT_EQ(d.name, "wire");
  ASSERT_EQ(d.sections.size(), 2u);
  EXPECT_EQ(d.sections[0].name, "shaft");  // proximal first
  EXPECT_EQ(d.sections[1].elements, 10);
  EXPECT_DOUBLE_EQ(d.sections[1].rest_curvature.z(), 100.0);
  EXPECT_NEAR(d.sections[0].section.shear_modulus, 6e10 / 2.66, 1.0);
  // Density from the URDF mass: m / (pi r^2 L).
  EXPECT_NEAR(d.sections[0].section.density, 0.0002 / (M_PI * 0.000178 * 0.000178 * 0.3), 1e-6);
  EXPECT_EQ(s.script.size(), 1u);
}

TEST_F(Loader, DriveLimitsAreReadAndChecked) {
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("inserted_length: 0.05"), 21,
               "inserted_length: 0.05\n    drive: {max_force: 2.5, max_torque: 0.004}");
  const SceneSpec s = loadSceneFile(write("scene.yaml", text));
  EXPECT_EQ(s.devices[0].drive.max_force, 2.5);
  EXPECT_EQ(s.devices[0].drive.max_torque, 0.004);
  EXPECT_TRUE(std::isinf(loadSceneFile(write("plain.yaml", kScene)).devices[0].drive.max_force));
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    drive: {max_force: -1}"),
      "scene.yaml", 10, "devices[0].drive.max_force", "must be a positive force");
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    drive: {max_torque: 0}"),
      "scene.yaml", 10, "devices[0].drive.max_torque", "must be a positive torque");
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    drive: {max_forse: 1}"),
      "scene.yaml", 10, "devices[0].drive.max_forse", "max_force");
}

TEST_F(Loader, LumenSettleIsReadAndChecked) {
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("effects: [gravity]\n"), 19,
               "effects: [gravity]\ncontact: {lumen_settle: 0.01}\n");
  EXPECT_EQ(loadSceneFile(write("scene.yaml", text)).contact.lumen_settle, 0.01);
  EXPECT_EQ(loadSceneFile(write("plain.yaml", kScene)).contact.lumen_settle, 0.03);
  expectNames(
      sceneError("effects: [gravity]\n", "effects: [gravity]\ncontact: {lumen_settle: 2}\n"),
      "scene.yaml", 4, "contact", "lumen_settle must lie in [1e-4, 1]");
}

TEST_F(Loader, MissingFieldIsNamed) {
  expectNames(deviceError("young_modulus=\"6e10\" ", ""), "wire.urdf", 15,
              "evsim_section[shaft]/young_modulus", "is missing");
}

TEST_F(Loader, NegativeRadiusIsNamed) {
  expectNames(
      deviceError("radius=\"0.000178\" length=\"0.3\"", "radius=\"-0.000178\" length=\"0.3\""),
      "wire.urdf", 6, "link[shaft]/cylinder/radius", "must be positive");
}

TEST_F(Loader, NanIsNamed) {
  expectNames(deviceError("young_modulus=\"2e10\"", "young_modulus=\"nan\""), "wire.urdf", 16,
              "evsim_section[tip]/young_modulus", "must be finite");
}

TEST_F(Loader, ZeroLengthSectionIsNamed) {
  expectNames(deviceError("length=\"0.02\"", "length=\"0\""), "wire.urdf", 11,
              "link[tip]/cylinder/length", "must be positive");
}

TEST_F(Loader, MissingExtensionOfALinkIsNamed) {
  const LoadError e = deviceError(
      "<evsim_section link=\"shaft\" young_modulus=\"6e10\" poisson_ratio=\"0.33\" "
      "elements=\"30\"/>",
      "");
  expectNames(e, "wire.urdf", 3, "evsim_section[shaft]", "every link needs");
}

TEST_F(Loader, InnerRadiusWiderThanOuterIsRefused) {
  expectNames(deviceError("elements=\"30\"", "elements=\"30\" inner_radius=\"0.001\""), "wire.urdf",
              15, "evsim_section[shaft]/inner_radius", "must be smaller");
}

TEST_F(Loader, DetachSectionMustNameALaterLink) {
  for (const char* link : {"shaft", "nowhere"})
    expectNames(
        deviceError("max_rotation_speed=\"6.28\"",
                    std::string("max_rotation_speed=\"6.28\" detach_section=\"") + link + "\""),
        "wire.urdf", 14, "evsim_device/detach_section", "must name a link after the first");
}

TEST_F(Loader, NegativeFrictionCoefficientIsRefused) {
  expectNames(deviceError("elements=\"30\"", "elements=\"30\" friction=\"-0.1\""), "wire.urdf", 15,
              "evsim_section[shaft]/friction", "must not be negative");
}

TEST_F(Loader, FrictionCoefficientPerSectionReachesTheSamplePoints) {
  fs::path p = dir_ / "wire.urdf";
  std::string text = kDevice;
  text.replace(text.find("elements=\"30\""), 13, "elements=\"30\" friction=\"0.25\"");
  text.replace(text.find("elements=\"10\""), 13, "elements=\"10\" friction=\"0.05\"");
  std::ofstream(p) << text;
  const DeviceModel m = buildDeviceModel(loadDeviceFile(p.string()));
  const std::vector<SamplePoint> samples = sampleDevice(m, 1e-3);
  EXPECT_EQ(samples.front().friction, 0.25);  // the shaft
  EXPECT_EQ(samples.back().friction, 0.05);   // the hydrophilic tip
}

TEST_F(Loader, MalformedXmlGivesItsLine) {
  const LoadError e = deviceError("</link>\n  <link name=\"tip\">", "<link name=\"tip\">");
  EXPECT_EQ(fs::path(e.file()).filename(), "wire.urdf");
  EXPECT_GT(e.line(), 0);
  EXPECT_NE(std::string(e.what()).find("malformed XML"), std::string::npos) << e.what();
}

TEST_F(Loader, UnknownDeviceInScriptIsNamed) {
  expectNames(sceneError("device: wire", "device: catheter"), "scene.yaml", 11, "script[0].device",
              "unknown device 'catheter'");
}

TEST_F(Loader, MissingSceneFieldIsNamed) {
  expectNames(sceneError("time_step: 0.001\n", ""), "scene.yaml", 1, "time_step", "is missing");
}

TEST_F(Loader, NanInSceneIsNamed) {
  expectNames(sceneError("[0, 0, -9.81]", "[0, .nan, -9.81]"), "scene.yaml", 4, "gravity",
              "must be finite");
}

TEST_F(Loader, UnknownEffectIsNamed) {
  expectNames(sceneError("[gravity]", "[gravity, magnetism]"), "scene.yaml", 3, "effects",
              "unknown effect 'magnetism'");
}

TEST_F(Loader, AMisspelledKeyIsRefusedWithTheNearestOne) {
  // A misspelled key must not run the scene with the default silently.
  expectNames(sceneError("gravity: [0", "gravty: [0"), "scene.yaml", 4, "gravty",
              "unknown key 'gravty' (did you mean 'gravity'?)");
  expectNames(sceneError("inserted_length: 0.05", "inserted_lenght: 0.05"), "scene.yaml", 9,
              "devices[0].inserted_lenght", "did you mean 'inserted_length'?");
  expectNames(sceneError("insertion: 0.01}", "insertoin: 0.01}"), "scene.yaml", 11,
              "script[0].insertoin", "did you mean 'insertion'?");
}

TEST_F(Loader, ADuplicateKeyIsRefused) {
  expectNames(sceneError("time_step: 0.001\n", "time_step: 0.001\ntime_step: 0.002\n"),
              "scene.yaml", 3, "time_step", "duplicate key 'time_step'");
}

TEST_F(Loader, AScalarWhereAMapBelongsIsAnErrorNotAnAbort) {
  expectNames(sceneError("  - {time: 0.5, device: wire, insertion: 0.01}", "  - 7"), "scene.yaml",
              11, "script[0]", "must be a map");
  expectNames(sceneError("effects: [gravity]\n", "effects: [gravity]\nvessels: 3\n"), "scene.yaml",
              4, "vessels", "must be a map");
  expectNames(sceneError("effects: [gravity]\n", "effects: [gravity]\ncontact: [1, 2]\n"),
              "scene.yaml", 4, "contact", "must be a map");
}

TEST_F(Loader, AFullInsertionAtTheNominalLengthIsValid) {
  // The device is 0.3 + 0.02 m long (its sections' sum); 0.32 is a full
  // insertion whatever the round-off of that sum.
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("inserted_length: 0.05"), 21, "inserted_length: 0.32");
  const SceneSpec s = loadSceneFile(write("scene.yaml", text));
  const DeviceModel m = buildDeviceModel(s.devices[0].device);
  EXPECT_LE(s.devices[0].inserted_length, m.length);
  EXPECT_NEAR(s.devices[0].inserted_length, 0.32, 1e-12);
}

TEST_F(Loader, AnElementLengthThatWouldExhaustMemoryIsRefused) {
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    max_element_length: 1e-9"),
      "scene.yaml", 10, "devices[0].max_element_length", "at least 1e-5 m");
}

TEST_F(Loader, AnAccessPointOutsideTheVesselsIsRefusedWithItsDistance) {
  // The carotid tree's descending aorta (radius 12 mm, its axis at x = 25
  // mm): 15 mm out along x, the point is about 3 mm beyond its wall.
  const std::string text = carotidScene("[0.040, -0.02, -0.13]");
  const SceneSpec spec = loadSceneFile(write("scene.yaml", text));
  try {
    buildSceneModel(spec);
    ADD_FAILURE() << "accepted";
  } catch (const LoadError& e) {
    EXPECT_EQ(e.line(), 8) << e.what();
    EXPECT_EQ(e.field(), "devices[0].access_point");
    EXPECT_NE(std::string(e.what()).find("mm beyond the wall"), std::string::npos) << e.what();
  }
}

TEST_F(Loader, DevicesPlacedThroughEachOtherAreRefusedWithTheElementsAndTheDepth) {
  // Two wires crossing in free space (the effect 'device_contact'): the
  // depth named is the deepest of every pair of their sample points,
  // found here by brute force on the same placement without the effect.
  write("wire.urdf", kDevice);
  std::string second = kDevice;
  second.replace(second.find("name=\"wire\""), 11, "name=\"crossing\"");
  write("crossing.urdf", second);
  std::string text = kScene;
  text.replace(text.find("effects: [gravity]"), 18, "effects: [gravity, device_contact]");
  text.replace(text.find("script:"), 7,
               "  - file: crossing.urdf\n    access_point: [0.015, -0.02, 0]\n"
               "    insertion_direction: [0, 1, 0]\n    inserted_length: 0.06\nscript:");
  const SceneSpec spec = loadSceneFile(write("scene.yaml", text));
  std::string message;
  try {
    buildSceneModel(spec);
    ADD_FAILURE() << "accepted";
  } catch (const LoadError& e) {
    message = e.what();
    EXPECT_EQ(e.field(), "devices[0]") << message;
    EXPECT_NE(message.find("of 'wire'"), std::string::npos) << message;
    EXPECT_NE(message.find("of 'crossing'"), std::string::npos) << message;
  }
  SceneSpec without = spec;
  without.effects = {"gravity"};
  const SceneModel m = buildSceneModel(without);
  const SimData d = makeData(m);
  double deepest = -1.0;
  for (const SamplePoint& a : m.samples[0])
    for (const SamplePoint& b : m.samples[1]) {
      const double distance = (samplePosition(m.devices[0], d.devices[0], a) -
                               samplePosition(m.devices[1], d.devices[1], b))
                                  .norm();
      deepest = std::max(deepest, a.radius + b.radius - distance);
    }
  const size_t at = message.find("overlap by ");
  ASSERT_NE(at, std::string::npos) << message;
  const double reported = std::stod(message.substr(at + 11)) * 1e-3;
  EXPECT_NEAR(reported, deepest, 1e-8) << message;
  EXPECT_GT(deepest, 0.1e-3);  // the axes cross: about the two radii
  std::printf("[ metric   ] crossing wires refused: %s\n", message.c_str());
}

TEST_F(Loader, AJointThatIsNotFixedIsRefused) {
  const LoadError e = deviceError("type=\"fixed\"", "type=\"continuous\"");
  EXPECT_EQ(e.field(), "joint[j]") << e.what();
  EXPECT_NE(std::string(e.what()).find("is not fixed"), std::string::npos) << e.what();
}

TEST_F(Loader, ANonIntegerSwcParentIsRefused) {
  const std::string swc = write("v.swc", "1 1 0 0 0 3 -1\n2 1 10 0 0 3 1.5\n");
  try {
    loadCenterlineFile(swc, 1e-3);
    ADD_FAILURE() << "accepted";
  } catch (const LoadError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "parent");
    EXPECT_NE(std::string(e.what()).find("not a whole number"), std::string::npos) << e.what();
  }
}

TEST_F(Loader, MissingDeviceFileIsNamed) {
  expectNames(sceneError("file: wire.urdf", "file: nowhere.urdf"), "scene.yaml", 6,
              "devices[0].file", "no device file");
}

TEST_F(Loader, InsertedLengthBeyondTheDeviceIsRefused) {
  expectNames(sceneError("inserted_length: 0.05", "inserted_length: 0.5"), "scene.yaml", 9,
              "devices[0].inserted_length", "must lie in");
}

TEST_F(Loader, MaxElementLengthRefinesOnlyCoarserSections) {
  write("wire.urdf", kDevice);
  std::string scene = kScene;
  const std::string at = "inserted_length: 0.05";
  scene.replace(scene.find(at), at.size(), at + "\n    max_element_length: 0.004");
  const SceneSpec s = loadSceneFile(write("scene.yaml", scene));
  EXPECT_EQ(s.devices[0].device.sections[0].elements, 75);  // 0.3 m: 30 -> ceil(0.3 / 0.004)
  EXPECT_EQ(s.devices[0].device.sections[1].elements, 10);  // 0.02 m: already 2 mm elements
}

TEST_F(Loader, NonPositiveMaxElementLengthIsNamed) {
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    max_element_length: 0"),
      "scene.yaml", 10, "devices[0].max_element_length", "must be at least 1e-5 m");
}

TEST_F(Loader, ScriptedCommandBeyondLimitsIsRefused) {
  expectNames(sceneError("insertion: 0.01", "insertion: 0.2"), "scene.yaml", 11, "script[0]",
              "exceeds the limit");
}

TEST_F(Loader, ACoarserVariantThanTheSceneAllowsIsRefused) {
  write("wire.urdf", kDevice);
  std::string scene = kScene;
  const std::string at = "inserted_length: 0.05";
  scene.replace(scene.find(at), at.size(), at + "\n    max_element_length: 0.004");
  SceneSpec spec = loadSceneFile(write("scene.yaml", scene));
  EXPECT_EQ(sceneLimitViolation(spec), "");
  EXPECT_NO_THROW(buildSceneModel(spec));
  // Halving the shaft's 75 elements (what `evsim bench --elements` or the
  // accuracy sweep does) gives 8.1 mm elements against the 4 mm limit.
  spec.devices[0].device.sections[0].elements = 37;
  EXPECT_NE(sceneLimitViolation(spec).find("allows at most 4 mm"), std::string::npos)
      << sceneLimitViolation(spec);
  try {
    buildSceneModel(spec);
    ADD_FAILURE() << "a coarser discretisation than the scene's limit was accepted";
  } catch (const LoadError& e) {
    expectNames(e, "scene.yaml", 10, "devices[0].max_element_length", "8.1");
  }
  spec.devices[0].device.sections[0].elements = 75;
  spec.time_step = 0.05;  // beyond one step per 25 Hz frame
  EXPECT_THROW(buildSceneModel(spec), LoadError);
}

TEST_F(Loader, MalformedYamlGivesItsLine) {
  const LoadError e = sceneError("  - file: wire.urdf", "  - file: [wire.urdf");
  EXPECT_GT(e.line(), 0);
  EXPECT_NE(std::string(e.what()).find("malformed YAML"), std::string::npos) << e.what();
}

TEST(ShippedConfig, EveryDeviceAndSceneLoadsAndSteps) {
  const auto scenes = shippedScenes();
  ASSERT_FALSE(scenes.empty());
  for (const auto& name : scenes) {
    const SceneModel model = loadScene(name);
    SimData data = makeData(model);
    for (int k = 0; k < 20; ++k) ASSERT_EQ(step(model, &data), StepStatus::kOk) << name;
  }
  for (const char* device : {"guidewire", "catheter", "coil"}) {
    const DeviceModel m =
        buildDeviceModel(loadDeviceFile(configDirectory() + "/devices/" + device + ".urdf"));
    EXPECT_GE(m.num_nodes, 100) << device;
  }
}

TEST(ShippedConfig, UnknownSceneNameListsTheShippedOnes) {
  try {
    resolveScenePath("no_such_scene");
    FAIL();
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("free_insertion"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

/// The shipped catheter + guidewire scene with `from` replaced by `to`,
/// loaded from a temporary copy; returns the error.
LoadError coaxialSceneError(const std::string& from, const std::string& to) {
  const fs::path config = configDirectory();
  std::ifstream in(config / "scenes" / "carotid_catheter.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t at; (at = text.find("../")) != std::string::npos;)
    text.replace(at, 3, (config / "").string());
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  const fs::path path = fs::temp_directory_path() / "evsim_coaxial_scene.yaml";
  std::ofstream(path) << text;
  try {
    loadSceneFile(path.string());
  } catch (const LoadError& e) {
    fs::remove(path);
    return e;
  }
  fs::remove(path);
  ADD_FAILURE() << "no error for " << to;
  return LoadError("", 0, "", "");
}

TEST(CoaxialLoader, UnknownOuterDeviceIsNamed) {
  const LoadError e = coaxialSceneError("inside: catheter", "inside: sheath");
  EXPECT_EQ(e.field(), "devices[1].inside");
  EXPECT_GT(e.line(), 0);
  EXPECT_NE(std::string(e.what()).find("unknown device 'sheath'"), std::string::npos) << e.what();
}

TEST(CoaxialLoader, InnerDeviceWiderThanTheLumenIsRefused) {
  const LoadError e = coaxialSceneError("devices/guidewire.urdf\n",
                                        "devices/catheter.urdf\n    name: inner_catheter\n");
  EXPECT_EQ(e.field(), "devices[1].inside");
  EXPECT_NE(std::string(e.what()).find("is wider than the lumen of 'catheter'"), std::string::npos)
      << e.what();
}

TEST(CoaxialLoader, PairingWithoutTheEffectIsRefused) {
  const LoadError e = coaxialSceneError("coaxial, ", "");
  EXPECT_EQ(e.field(), "devices[1].inside");
  EXPECT_NE(std::string(e.what()).find("needs the effect 'coaxial'"), std::string::npos)
      << e.what();
}

TEST(CoaxialLoader, AnInnerDeviceHasNoAccessPointOfItsOwn) {
  const LoadError e =
      coaxialSceneError("inside: catheter", "inside: catheter\n    access_point: [0, 0, 0]");
  EXPECT_EQ(e.field(), "devices[1].access_point");
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

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
  fails("aorta", "also names branch 0");
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

TEST_F(Loader, AWireAimedAcrossItsVesselAndANetworkThatCannotGrowAreWarned) {
  // The carotid tree's descending aorta runs along z: entering along x, the
  // wire meets the wall 12 mm ahead.
  std::string text = carotidScene("[0.025, -0.020, -0.130]");
  const SceneModel across = buildSceneModel(loadSceneFile(write("across.yaml", text)));
  ASSERT_EQ(across.warnings.size(), 1u);
  EXPECT_NE(across.warnings[0].find("devices[0] (wire) enters at 90 degrees"), std::string::npos)
      << across.warnings[0];
  text.replace(text.find("insertion_direction: [1, 0, 0]"), 30, "insertion_direction: [0, 0, 1]");
  EXPECT_TRUE(buildSceneModel(loadSceneFile(write("along.yaml", text))).warnings.empty());
  // Every leaf of the tree is narrower than min_radius: no vessel grows.
  const std::string swc = configDirectory() + "/vessels/carotid.swc";
  text.replace(
      text.find("vessels: {centerline: " + swc + "}"), swc.size() + 23,
      "vessels: {centerline: " + swc + ", network: {seed: 1, vessels: 10, min_radius: 0.05}}");
  const SceneModel none = buildSceneModel(loadSceneFile(write("network.yaml", text)));
  ASSERT_EQ(none.warnings.size(), 1u);
  EXPECT_NE(none.warnings[0].find("grew 0 of 10 vessels"), std::string::npos) << none.warnings[0];
}

TEST_F(Loader, SleepOptionsAreChecked) {
  const LoadError word = sceneError("devices:", "sleep: maybe\ndevices:");
  expectNames(word, "scene.yaml", 5, "sleep", "true, false or a map");
  const LoadError range = sceneError("devices:", "sleep: {displacement: -1}\ndevices:");
  expectNames(range, "scene.yaml", 5, "sleep", "displacement must lie in");
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("devices:"), 8, "sleep: false\ndevices:");
  EXPECT_FALSE(loadSceneFile(write("off.yaml", text)).sleep.enabled);
}

}  // namespace
}  // namespace evsim
