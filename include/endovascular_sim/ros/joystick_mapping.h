// Joystick to drive commands (ROS-free: the node passes the axes and buttons
// of sensor_msgs/Joy). A dead-man button must be held for anything to move;
// one axis inserts or retracts, one rotates; a button switches the driven
// device. Read from config/joystick/*.yaml (documented there).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "endovascular_sim/mechanics/introducer.h"

namespace evsim {

struct JoystickMapping {
  int insertion_axis{1};          // index into Joy.axes
  double insertion_scale{0.02};   // [m/s] at full deflection (negative: inverted axis)
  int rotation_axis{3};           // index into Joy.axes
  double rotation_scale{3.1416};  // [rad/s] at full deflection
  int deadman_button{4};          // index into Joy.buttons; -1: no dead-man (not advised)
  int switch_device_button{0};    // index into Joy.buttons; -1: always the first device
  double deadzone{0.1};           // |axis| below this counts as zero, in [0, 1)
};

/// Reads a mapping (throws LoadError naming the file, line and field).
JoystickMapping loadJoystickMapping(const std::string& path);

/// What the joystick has done so far (edges are detected against it).
struct JoystickState {
  int device{0};  // index of the driven device
  bool switch_was_pressed{false};
  bool moving{false};  // a non-zero command was sent and not yet stopped
};

struct JoystickOutcome {
  std::vector<std::pair<int, DriveCommand>> commands;  // (device index, command)
  bool switched{false};                                // the driven device changed
  std::string problem;  // the message was ignored, and why ("" when used)
};

/// Maps one Joy message. Velocity commands go to the driven device while the
/// dead-man button is held; releasing it, or switching device, stops the
/// device that was moving. A message too short for the mapping's indices is
/// ignored with a problem naming the index.
JoystickOutcome mapJoystick(const JoystickMapping& mapping, const std::vector<float>& axes,
                            const std::vector<int>& buttons, int num_devices, JoystickState* state);

}  // namespace evsim
