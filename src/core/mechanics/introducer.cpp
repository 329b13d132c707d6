// Insertion and rotation at the proximal end. Declared and documented in
// endovascular_sim/mechanics/introducer.h.
#include "endovascular_sim/mechanics/introducer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace evsim {
namespace {

Mat3 rotationX(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix(); }

double clampAbs(double v, double limit) { return std::max(-limit, std::min(limit, v)); }

}  // namespace

int lastHeldNode(const DeviceModel& model, double inserted_length) {
  const double s_access = model.length - inserted_length;
  const double eps = 1e-12 * model.length;
  int k = 0;
  while (k + 1 < model.num_nodes && model.node_s[k + 1] <= s_access + eps) ++k;
  return k;
}

void heldPose(const DeviceModel& model, const Introducer& intro, double inserted_length,
              double rotation_angle, int node, Vec3* position, Mat3* rotation) {
  *position = heldPosition(model, intro, inserted_length, node);
  *rotation = heldRotation(intro, rotation_angle, model.rest_twist[node]);
}

Vec3 heldPosition(const DeviceModel& model, const Introducer& intro, double inserted_length,
                  int node) {
  const double behind = model.length - inserted_length - model.node_s[node];
  return intro.access_point - behind * intro.frame.col(0);
}

Mat3 heldRotation(const Introducer& intro, double rotation_angle, double twist) {
  return intro.frame * rotationX(rotation_angle + twist);
}

DeviceState placeDevice(const DeviceModel& model, const Introducer& intro, double inserted_length,
                        double rotation_angle) {
  DeviceState s = restState(model);
  s.inserted_length = inserted_length;
  s.rotation_angle = rotation_angle;
  const int k = lastHeldNode(model, inserted_length);
  Mat3 Rk;
  for (int i = 0; i <= k; ++i) {
    heldPose(model, intro, inserted_length, rotation_angle, i, &s.position[i], &Rk);
    s.rotation[i] = Quat(Rk);
  }
  const Mat3 T = Rk * model.rest_rotation[k].transpose();
  for (int i = k + 1; i < model.num_nodes; ++i) {
    s.position[i] = s.position[k] + T * (model.rest_position[i] - model.rest_position[k]);
    s.rotation[i] = Quat(T * model.rest_rotation[i]);
  }
  return s;
}

std::string validateDriveCommand(const DriveCommand& command, const DeviceModel& model) {
  std::ostringstream why;
  if (!std::isfinite(command.insertion) || !std::isfinite(command.rotation)) {
    why << "insertion and rotation must be finite numbers";
  } else if (command.mode == DriveCommand::Mode::kVelocity) {
    if (std::abs(command.insertion) > model.max_insertion_speed)
      why << "insertion speed " << command.insertion << " m/s exceeds the limit "
          << model.max_insertion_speed << " m/s of device '" << model.name << "'";
    else if (std::abs(command.rotation) > model.max_rotation_speed)
      why << "rotation speed " << command.rotation << " rad/s exceeds the limit "
          << model.max_rotation_speed << " rad/s of device '" << model.name << "'";
  } else if (command.insertion < 0.0 || command.insertion > model.length) {
    why << "target inserted length " << command.insertion << " m is outside [0, " << model.length
        << "] m for device '" << model.name << "'";
  } else if (std::abs(command.rotation) > kMaxRotationTarget) {
    why << "target rotation " << command.rotation << " rad is beyond +-" << kMaxRotationTarget
        << " rad (1000 turns) for device '" << model.name << "'";
  }
  return why.str();
}

void advanceDrive(const DriveCommand& command, const DeviceModel& model, double dt,
                  DeviceState* state, DriveStall stall) {
  if (state->released) return;
  double d_insert, d_rotate;
  if (command.mode == DriveCommand::Mode::kVelocity) {
    d_insert = command.insertion * dt;
    d_rotate = command.rotation * dt;
  } else {
    d_insert = command.insertion - state->inserted_length;
    d_rotate = command.rotation - state->rotation_angle;
  }
  d_insert = clampAbs(d_insert, model.max_insertion_speed * dt);
  d_rotate = clampAbs(d_rotate, model.max_rotation_speed * dt);
  if (stall.insertion * d_insert > 0.0) d_insert = 0.0;
  if (stall.rotation * d_rotate > 0.0) d_rotate = 0.0;
  state->inserted_length = std::clamp(state->inserted_length + d_insert, 0.0, model.length);
  state->rotation_angle += d_rotate;
}

}  // namespace evsim
