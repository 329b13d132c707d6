// Joystick mapping: shipped files, malformed files, and the mapping itself
// against hand-computed commands.
#include "endovascular_sim/ros/joystick_mapping.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

const char* kMapping =
    "insertion_axis: 1\n"
    "insertion_scale: 0.02\n"
    "rotation_axis: 3\n"
    "rotation_scale: 2.0\n"
    "deadman_button: 4\n"
    "switch_device_button: 0\n"
    "deadzone: 0.1\n";

std::string writeMapping(const std::string& text) {
  const fs::path path = fs::temp_directory_path() / "evsim_joystick_test.yaml";
  std::ofstream(path) << text;
  return path.string();
}

LoadError errorFor(const std::string& from, const std::string& to) {
  std::string text = kMapping;
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  try {
    loadJoystickMapping(writeMapping(text));
  } catch (const LoadError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for " << to;
  return LoadError("", 0, "", "");
}

TEST(JoystickMapping, ShippedMappingsLoad) {
  for (const char* name : {"xbox", "ps4"}) {
    const JoystickMapping m =
        loadJoystickMapping(std::string(EVSIM_CONFIG_DIR) + "/joystick/" + name + ".yaml");
    EXPECT_NE(m.insertion_axis, m.rotation_axis) << name;
    EXPECT_GE(m.deadman_button, 0) << name;  // shipped mappings all have a dead-man button
  }
}

TEST(JoystickMapping, FileValuesAreRead) {
  const JoystickMapping m = loadJoystickMapping(writeMapping(kMapping));
  EXPECT_EQ(m.insertion_axis, 1);
  EXPECT_DOUBLE_EQ(m.insertion_scale, 0.02);
  EXPECT_EQ(m.rotation_axis, 3);
  EXPECT_DOUBLE_EQ(m.rotation_scale, 2.0);
  EXPECT_EQ(m.deadman_button, 4);
  EXPECT_EQ(m.switch_device_button, 0);
  EXPECT_DOUBLE_EQ(m.deadzone, 0.1);
}

TEST(JoystickMapping, BadFilesNameLineAndField) {
  struct Case {
    const char *from, *to, *field, *words;
    int line;
  };
  const Case cases[] = {
      {"insertion_axis: 1\n", "", "insertion_axis", "is missing", 1},
      {"insertion_axis: 1", "insertion_axis: -2", "insertion_axis", "axis index", 1},
      {"rotation_axis: 3", "rotation_axis: x", "rotation_axis", "whole number", 3},
      {"rotation_scale: 2.0", "rotation_scale: 0", "rotation_scale", "zero", 4},
      {"deadman_button: 4", "deadman_button: -3", "deadman_button", "-1 for none", 5},
      {"switch_device_button: 0", "switch_device_button: 4", "switch_device_button", "differ", 6},
      {"deadzone: 0.1", "deadzone: 1.5", "deadzone", "[0, 1)", 7},
      {"rotation_axis: 3", "rotation_axis: 1", "rotation_axis", "differ", 3},
  };
  for (const Case& c : cases) {
    const LoadError e = errorFor(c.from, c.to);
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("evsim_joystick_test.yaml"), std::string::npos);
  }
}

TEST(JoystickMapping, MalformedYamlNamesTheLine) {
  try {
    loadJoystickMapping(writeMapping("insertion_axis: 1\nrotation_axis: [3\n"));
    FAIL() << "no error";
  } catch (const LoadError& e) {
    EXPECT_GE(e.line(), 2) << e.what();
    EXPECT_NE(std::string(e.what()).find("malformed YAML"), std::string::npos);
  }
}

struct Pad {
  std::vector<float> axes = std::vector<float>(4, 0.0f);
  std::vector<int> buttons = std::vector<int>(5, 0);
};

TEST(JoystickMapping, NothingMovesWithoutTheDeadmanButton) {
  const JoystickMapping m = loadJoystickMapping(writeMapping(kMapping));
  JoystickState state;
  Pad pad;
  pad.axes[1] = 1.0f;
  pad.axes[3] = -1.0f;
  const JoystickOutcome out = mapJoystick(m, pad.axes, pad.buttons, 2, &state);
  EXPECT_TRUE(out.problem.empty());
  EXPECT_TRUE(out.commands.empty());
}

TEST(JoystickMapping, AxesScaleWithTheDeadzoneRemoved) {
  const JoystickMapping m = loadJoystickMapping(writeMapping(kMapping));
  JoystickState state;
  Pad pad;
  pad.buttons[4] = 1;
  pad.axes[1] = 0.55f;  // (0.55 - 0.1) / 0.9 = 0.5 of full scale
  pad.axes[3] = -1.0f;
  const JoystickOutcome out = mapJoystick(m, pad.axes, pad.buttons, 2, &state);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].first, 0);
  const DriveCommand& c = out.commands[0].second;
  EXPECT_EQ(c.mode, DriveCommand::Mode::kVelocity);
  EXPECT_NEAR(c.insertion, 0.5 * 0.02, 1e-8);
  EXPECT_NEAR(c.rotation, -2.0, 1e-12);
  pad.axes[1] = 0.05f;  // inside the deadzone
  pad.axes[3] = 0.0f;
  const JoystickOutcome still = mapJoystick(m, pad.axes, pad.buttons, 2, &state);
  ASSERT_EQ(still.commands.size(), 1u);  // the stop of the moving device
  EXPECT_EQ(still.commands[0].second.insertion, 0.0);
  EXPECT_TRUE(mapJoystick(m, pad.axes, pad.buttons, 2, &state).commands.empty());
}

TEST(JoystickMapping, ReleasingTheDeadmanStopsTheDevice) {
  const JoystickMapping m = loadJoystickMapping(writeMapping(kMapping));
  JoystickState state;
  Pad pad;
  pad.buttons[4] = 1;
  pad.axes[1] = 1.0f;
  mapJoystick(m, pad.axes, pad.buttons, 1, &state);
  pad.buttons[4] = 0;
  const JoystickOutcome out = mapJoystick(m, pad.axes, pad.buttons, 1, &state);
  ASSERT_EQ(out.commands.size(), 1u);
  EXPECT_EQ(out.commands[0].second.insertion, 0.0);
  EXPECT_EQ(out.commands[0].second.rotation, 0.0);
}

TEST(JoystickMapping, SwitchButtonCyclesDevicesOnItsRisingEdge) {
  const JoystickMapping m = loadJoystickMapping(writeMapping(kMapping));
  JoystickState state;
  Pad pad;
  pad.buttons[4] = 1;
  pad.axes[1] = 1.0f;
  mapJoystick(m, pad.axes, pad.buttons, 3, &state);  // device 0 moves
  pad.buttons[0] = 1;
  const JoystickOutcome out = mapJoystick(m, pad.axes, pad.buttons, 3, &state);
  EXPECT_TRUE(out.switched);
  EXPECT_EQ(state.device, 1);
  ASSERT_EQ(out.commands.size(), 2u);
  EXPECT_EQ(out.commands[0].first, 0);  // the previous device is stopped
  EXPECT_EQ(out.commands[0].second.insertion, 0.0);
  EXPECT_EQ(out.commands[1].first, 1);  // the new one is driven
  EXPECT_NEAR(out.commands[1].second.insertion, 0.02, 1e-12);
  EXPECT_FALSE(mapJoystick(m, pad.axes, pad.buttons, 3, &state).switched);  // still held
  pad.buttons[0] = 0;
  mapJoystick(m, pad.axes, pad.buttons, 3, &state);
  pad.buttons[0] = 1;
  mapJoystick(m, pad.axes, pad.buttons, 3, &state);
  pad.buttons[0] = 0;
  mapJoystick(m, pad.axes, pad.buttons, 3, &state);
  pad.buttons[0] = 1;
  mapJoystick(m, pad.axes, pad.buttons, 3, &state);
  EXPECT_EQ(state.device, 0);  // 1 -> 2 -> 0
}

TEST(JoystickMapping, ShortMessagesAreRefusedByIndex) {
  const JoystickMapping m = loadJoystickMapping(writeMapping(kMapping));
  JoystickState state;
  const JoystickOutcome a = mapJoystick(m, {0.0f, 1.0f}, {0, 0, 0, 0, 1}, 1, &state);
  EXPECT_NE(a.problem.find("rotation_axis is 3"), std::string::npos) << a.problem;
  EXPECT_TRUE(a.commands.empty());
  const JoystickOutcome b = mapJoystick(m, {0.0f, 1.0f, 0.0f, 0.0f}, {1}, 1, &state);
  EXPECT_NE(b.problem.find("deadman_button is 4"), std::string::npos) << b.problem;
}

}  // namespace
}  // namespace evsim
