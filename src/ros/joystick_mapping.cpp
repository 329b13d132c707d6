// Joystick to drive commands (ROS-free: the node passes the axes and buttons
// of sensor_msgs/Joy). Declared and documented in
// endovascular_sim/ros/joystick_mapping.h.
#include "endovascular_sim/ros/joystick_mapping.h"

#include <cmath>

#include "endovascular_sim/scene/yaml_reader.h"

namespace evsim {
namespace {

double applyDeadzone(double value, double deadzone) {
  const double magnitude = std::abs(value);
  if (magnitude <= deadzone) return 0.0;
  return std::copysign(std::min(1.0, (magnitude - deadzone) / (1.0 - deadzone)), value);
}

DriveCommand velocity(double insertion, double rotation) {
  DriveCommand c;
  c.mode = DriveCommand::Mode::kVelocity;
  c.insertion = insertion;
  c.rotation = rotation;
  return c;
}

}  // namespace

JoystickMapping loadJoystickMapping(const std::string& path) {
  const YamlReader r(path);
  const YAML::Node root = r.load();
  if (!root.IsMap()) r.fail(root, "", "a joystick mapping is a YAML map");
  JoystickMapping m;
  const auto index = [&](const char* key, int* out, int lowest) {
    const YAML::Node n = r.required(root, key, key);
    *out = r.integer(n, key);
    if (*out < lowest)
      r.fail(n, key,
             lowest < 0 ? "must be a button index >= 0, or -1 for none"
                        : "must be an axis index >= 0");
  };
  const auto scale = [&](const char* key, double* out) {
    const YAML::Node n = r.required(root, key, key);
    *out = r.number(n, key);
    if (*out == 0.0) r.fail(n, key, "must not be zero");
  };
  index("insertion_axis", &m.insertion_axis, 0);
  scale("insertion_scale", &m.insertion_scale);
  index("rotation_axis", &m.rotation_axis, 0);
  scale("rotation_scale", &m.rotation_scale);
  index("deadman_button", &m.deadman_button, -1);
  index("switch_device_button", &m.switch_device_button, -1);
  m.deadzone = r.number(root, "deadzone", "", m.deadzone);
  if (!(m.deadzone >= 0.0 && m.deadzone < 1.0))
    r.fail(root["deadzone"], "deadzone", "must lie in [0, 1)");
  if (m.insertion_axis == m.rotation_axis)
    r.fail(root["rotation_axis"], "rotation_axis", "must differ from insertion_axis");
  if (m.deadman_button >= 0 && m.deadman_button == m.switch_device_button)
    r.fail(root["switch_device_button"], "switch_device_button", "must differ from deadman_button");
  return m;
}

JoystickOutcome mapJoystick(const JoystickMapping& m, const std::vector<float>& axes,
                            const std::vector<int>& buttons, int num_devices,
                            JoystickState* state) {
  JoystickOutcome out;
  const int num_axes = static_cast<int>(axes.size());
  const int num_buttons = static_cast<int>(buttons.size());
  const auto missing = [&](const char* what, int index, int available) {
    out.problem = "Joy message has " + std::to_string(available) + " " +
                  (what[0] == 'a' ? "axes" : "buttons") + "; the mapping's " + what + " is " +
                  std::to_string(index);
  };
  if (m.insertion_axis >= num_axes) {
    missing("axis insertion_axis", m.insertion_axis, num_axes);
  } else if (m.rotation_axis >= num_axes) {
    missing("axis rotation_axis", m.rotation_axis, num_axes);
  } else if (m.deadman_button >= num_buttons) {
    missing("button deadman_button", m.deadman_button, num_buttons);
  } else if (m.switch_device_button >= num_buttons) {
    missing("button switch_device_button", m.switch_device_button, num_buttons);
  }
  if (!out.problem.empty() || num_devices <= 0) return out;
  if (state->device >= num_devices) state->device = 0;

  const bool switch_pressed = m.switch_device_button >= 0 && buttons[m.switch_device_button] != 0;
  if (switch_pressed && !state->switch_was_pressed && num_devices > 1) {
    if (state->moving) out.commands.emplace_back(state->device, velocity(0.0, 0.0));
    state->moving = false;
    state->device = (state->device + 1) % num_devices;
    out.switched = true;
  }
  state->switch_was_pressed = switch_pressed;

  const bool enabled = m.deadman_button < 0 || buttons[m.deadman_button] != 0;
  if (!enabled) {
    if (state->moving) out.commands.emplace_back(state->device, velocity(0.0, 0.0));
    state->moving = false;
    return out;
  }
  const double insertion = m.insertion_scale * applyDeadzone(axes[m.insertion_axis], m.deadzone);
  const double rotation = m.rotation_scale * applyDeadzone(axes[m.rotation_axis], m.deadzone);
  if (insertion != 0.0 || rotation != 0.0 || state->moving)
    out.commands.emplace_back(state->device, velocity(insertion, rotation));
  state->moving = insertion != 0.0 || rotation != 0.0;
  return out;
}

}  // namespace evsim
