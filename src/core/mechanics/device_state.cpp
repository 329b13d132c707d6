// The changing state of one device (part of the simulation Data). Declared and
// documented in endovascular_sim/mechanics/device_state.h.
#include "endovascular_sim/mechanics/device_state.h"

#include <algorithm>

namespace evsim {

namespace {

template <typename T>
void copyInto(const std::vector<T>& from, std::vector<T>* to) {
  if (to->size() == from.size())
    std::copy(from.begin(), from.end(), to->begin());
  else
    *to = from;
}

}  // namespace

void copyState(const DeviceState& from, DeviceState* to) {
  copyInto(from.position, &to->position);
  copyInto(from.rotation, &to->rotation);
  copyInto(from.velocity, &to->velocity);
  copyInto(from.angular_velocity, &to->angular_velocity);
  to->inserted_length = from.inserted_length;
  to->rotation_angle = from.rotation_angle;
  to->released = from.released;
  to->cut_element = from.cut_element;
}

DeviceState restState(const DeviceModel& model, const Mat3& R, const Vec3& t) {
  DeviceState s;
  const int n = model.num_nodes;
  s.position.resize(n);
  s.rotation.resize(n);
  for (int i = 0; i < n; ++i) {
    s.position[i] = R * model.rest_position[i] + t;
    s.rotation[i] = Quat(R * model.rest_rotation[i]);
  }
  s.velocity.assign(n, Vec3::Zero());
  s.angular_velocity.assign(n, Vec3::Zero());
  return s;
}

double kineticEnergy(const DeviceModel& model, const DeviceState& state) {
  double e = 0.0;
  for (int i = 0; i < model.num_nodes; ++i) {
    const Vec3 w_body = state.rotation[i].conjugate() * state.angular_velocity[i];
    e += 0.5 * model.node_mass[i] * state.velocity[i].squaredNorm();
    e += 0.5 * w_body.dot(model.node_inertia[i].cwiseProduct(w_body));
  }
  return e;
}

}  // namespace evsim
