// The loader tests' fixture: a device and a scene written into a temporary
// folder, variants with one line changed, and the check that an error names
// the file, the line and the field. Shared by loader_test.cpp,
// loader_vessels_test.cpp and loader_xray_test.cpp.
#pragma once

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
namespace test {

namespace fs = std::filesystem;

inline const char* kDevice = R"(<?xml version="1.0"?>
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

inline const char* kScene = R"(name: test
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

inline void expectNames(const LoadError& e, const std::string& file, int line,
                        const std::string& field, const std::string& words) {
  EXPECT_EQ(fs::path(e.file()).filename().string(), file) << e.what();
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.field(), field) << e.what();
  EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find(file + ":" + std::to_string(line)), std::string::npos)
      << e.what();
}

}  // namespace test
}  // namespace evsim
