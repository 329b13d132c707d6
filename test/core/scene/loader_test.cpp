// Device and scene files: shipped ones load; each kind of bad input gives an
// error that names the file, the line and the field, and nothing crashes.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/scene/scene_schema.h"
#include "endovascular_sim/sim/simulation.h"
#include "loader_fixture.h"

namespace evsim {
namespace {

using test::expectNames;
using test::kDevice;
using test::kScene;
using test::Loader;
namespace fs = std::filesystem;

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
               "inserted_length: 0.05\n    drive: {max_force: 2.5, max_torque: 0.004, "
               "valve_friction: 0.3, valve_torque: 0.0002}");
  const SceneSpec s = loadSceneFile(write("scene.yaml", text));
  EXPECT_EQ(s.devices[0].drive.max_force, 2.5);
  EXPECT_EQ(s.devices[0].drive.max_torque, 0.004);
  EXPECT_EQ(s.devices[0].drive.valve_friction, 0.3);
  EXPECT_EQ(s.devices[0].drive.valve_torque, 0.0002);
  EXPECT_EQ(loadSceneFile(write("plain.yaml", kScene)).devices[0].drive.valve_friction, 0.0);
  // Omitted: the device file's limits, a hand's where it gives none.
  const DriveSpec plain = loadSceneFile(write("plain.yaml", kScene)).devices[0].drive;
  EXPECT_EQ(plain.max_force, kDefaultDriveMaxForce);
  EXPECT_EQ(plain.max_torque, kDefaultDriveMaxTorque);
  std::string own = kDevice;
  own.replace(own.find("max_rotation_speed=\"6.28\""), 25,
              "max_rotation_speed=\"6.28\" drive_max_force=\"3\" drive_max_torque=\"0.002\"");
  write("wire.urdf", own);
  const DriveSpec from_file = loadSceneFile(write("plain.yaml", kScene)).devices[0].drive;
  EXPECT_EQ(from_file.max_force, 3.0);
  EXPECT_EQ(from_file.max_torque, 0.002);
  // The scene's word wins, one limit at a time; `unlimited` is kinematic.
  text = kScene;
  text.replace(text.find("inserted_length: 0.05"), 21,
               "inserted_length: 0.05\n    drive: {max_force: unlimited}");
  const DriveSpec kinematic = loadSceneFile(write("scene.yaml", text)).devices[0].drive;
  EXPECT_TRUE(std::isinf(kinematic.max_force));
  EXPECT_EQ(kinematic.max_torque, 0.002);
  write("wire.urdf", kDevice);
  expectNames(sceneError("inserted_length: 0.05",
                         "inserted_length: 0.05\n    drive: {max_torque: unlimted}"),
              "scene.yaml", 10, "devices[0].drive.max_torque", "unlimited");
  expectNames(deviceError("max_rotation_speed=\"6.28\"",
                          "max_rotation_speed=\"6.28\" drive_max_force=\"0\""),
              "wire.urdf", 14, "evsim_device/drive_max_force", "must be positive");
  expectNames(deviceError("max_rotation_speed=\"6.28\"",
                          "max_rotation_speed=\"6.28\" drive_max_torque=\"inf\""),
              "wire.urdf", 14, "evsim_device/drive_max_torque", "must be finite");
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    drive: {max_force: -1}"),
      "scene.yaml", 10, "devices[0].drive.max_force", "must be above 0 N, got -1");
  expectNames(
      sceneError("inserted_length: 0.05", "inserted_length: 0.05\n    drive: {max_torque: 0}"),
      "scene.yaml", 10, "devices[0].drive.max_torque", "must be above 0 N m, got 0");
  expectNames(sceneError("inserted_length: 0.05",
                         "inserted_length: 0.05\n    drive: {valve_friction: -0.1}"),
              "scene.yaml", 10, "devices[0].drive.valve_friction", "[0, 100] N");
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
  EXPECT_EQ(loadSceneFile(write("plain.yaml", kScene)).contact.lumen_settle, 0.1);
  expectNames(
      sceneError("effects: [gravity]\n", "effects: [gravity]\ncontact: {lumen_settle: 2}\n"),
      "scene.yaml", 4, "contact.lumen_settle", "must lie in [1e-4, 1], got 2");
}

TEST_F(Loader, PairToleranceIsReadAndChecked) {
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("effects: [gravity]\n"), 19,
               "effects: [gravity]\ncontact: {pair_tolerance: 5.0e-6}\n");
  EXPECT_EQ(loadSceneFile(write("scene.yaml", text)).contact.pair_tolerance, 5e-6);
  EXPECT_EQ(loadSceneFile(write("plain.yaml", kScene)).contact.pair_tolerance, 0.0);
  expectNames(
      sceneError("effects: [gravity]\n", "effects: [gravity]\ncontact: {pair_tolerance: 0.001}\n"),
      "scene.yaml", 4, "contact.pair_tolerance", "must lie in [0, 1e-4] m, got 0.001");
}

TEST_F(Loader, ARetiredContactKeyIsRefusedWithWhatReplacedIt) {
  // Each retired key (either setting gave the same answer, or the solver owns it) is refused by the
  // loader and by the schema check, with its own reason, not as unknown.
  for (const RetiredKey& retired : retiredSceneKeys()) {
    const std::string key = retired.path.substr(retired.path.find('.') + 1);
    SCOPED_TRACE(retired.path);
    expectNames(
        sceneError("effects: [gravity]\n", "effects: [gravity]\ncontact: {" + key + ": false}\n"),
        "scene.yaml", 4, retired.path, "is no longer a scene key");
    const std::vector<SchemaProblem> problems =
        checkSceneSchema(YAML::Load("contact: {" + key + ": true}"));
    int told = 0;  // (the keys this fragment lacks are problems too)
    for (const SchemaProblem& p : problems)
      if (p.key == retired.path) {
        EXPECT_EQ(p.what, retired.why);
        ++told;
      }
    EXPECT_EQ(told, 1);
  }
  // What replaced them: the default a scene without the key runs with.
  const ContactOptions defaults = loadSceneFile(write("plain.yaml", kScene)).contact;
  EXPECT_TRUE(defaults.interior_balls && defaults.detect_on_first_iterate &&
              defaults.columns_on_demand && defaults.slid_pair_warm_start);
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

TEST_F(Loader, AVisualCylinderBesideTheCollisionOneIsCheckedToo) {
  expectNames(deviceError("</collision>\n  </link>\n  <link name=\"tip\">",
                          "</collision>\n    <visual><geometry><cylinder radius=\"-0.001\" "
                          "length=\"0.3\"/></geometry></visual>\n  </link>\n  <link "
                          "name=\"tip\">"),
              "wire.urdf", 7, "link[shaft]/visual/geometry/cylinder/radius", "must be positive");
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
              "must be a list of 3 finite numbers");
}

TEST_F(Loader, BloodViscosityOutOfRangeIsNamed) {
  expectNames(
      sceneError("gravity: [0, 0, -9.81]\n", "gravity: [0, 0, -9.81]\nblood_viscosity: 0\n"),
      "scene.yaml", 5, "blood_viscosity", "must lie in (0, 0.1] Pa s");
}

TEST_F(Loader, BloodDensityOutOfRangeIsNamed) {
  expectNames(
      sceneError("gravity: [0, 0, -9.81]\n", "gravity: [0, 0, -9.81]\nblood_density: 10600\n"),
      "scene.yaml", 5, "blood_density", "must lie in [500, 2000] kg/m^3");
}

TEST_F(Loader, UnknownEffectIsNamed) {
  expectNames(sceneError("[gravity]", "[gravity, magnetism]"), "scene.yaml", 3, "effects[1]",
              "'magnetism' must be one of gravity, vessel_motion, device_contact");
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

TEST_F(Loader, ADeviceLengthResizesItsShaftAtTheFilesElementLength) {
  // The file's device: a 0.3 m shaft in 30 elements and a 0.02 m tip. At
  // 1.02 m the shaft is 1.0 m in 1 cm elements; the tip is the file's, and
  // an insertion beyond the file's length is valid.
  write("wire.urdf", kDevice);
  std::string scene = kScene;
  const std::string at = "inserted_length: 0.05";
  scene.replace(scene.find(at), at.size(), "length: 1.02\n    inserted_length: 0.5");
  const SceneSpec s = loadSceneFile(write("scene.yaml", scene));
  const DeviceSpec& d = s.devices[0].device;
  EXPECT_NEAR(d.sections[0].length, 1.0, 1e-12);
  EXPECT_EQ(d.sections[0].elements, 100);
  EXPECT_NEAR(d.sections[1].length, 0.02, 1e-15);
  EXPECT_EQ(d.sections[1].elements, 10);
  EXPECT_NEAR(buildDeviceModel(d).length, 1.02, 1e-12);
  EXPECT_NEAR(s.devices[0].inserted_length, 0.5, 1e-15);
}

TEST_F(Loader, ADeviceLengthShorterThanItsDistalSectionsIsNamed) {
  expectNames(sceneError("inserted_length: 0.05", "length: 0.02\n    inserted_length: 0.01"),
              "scene.yaml", 9, "devices[0].length", "must lie in [0.021, 10] m");
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
