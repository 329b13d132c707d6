// The changing state of one device (part of the simulation Data).
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"

namespace evsim {

struct DeviceState {
  std::vector<Vec3> position;          // node positions, world [m]
  std::vector<Quat> rotation;          // node frames, world
  std::vector<Vec3> velocity;          // [m/s]
  std::vector<Vec3> angular_velocity;  // world [rad/s]
  double inserted_length{0.0};         // material past the access point [m]
  double rotation_angle{0.0};          // commanded proximal rotation [rad]
  bool released{false};                // detached: no node held, commands ignored
  int cut_element{-1};  // after detach: this element (pusher | coil) carries no stiffness and
                        // no contact, and no node beyond it is held (-1: not detached)
};

/// State at rest in the model's rest shape, moved by the rigid motion (R, t).
DeviceState restState(const DeviceModel& model, const Mat3& R = Mat3::Identity(),
                      const Vec3& t = Vec3::Zero());

/// Copies `from` into *to, into to's own node arrays where their sizes
/// match (a view of them, as the Python front's arrays are, stays valid).
void copyState(const DeviceState& from, DeviceState* to);

/// Kinetic energy [J] (translational and rotational).
double kineticEnergy(const DeviceModel& model, const DeviceState& state);

}  // namespace evsim
