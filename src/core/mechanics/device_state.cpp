// The changing state of one device (part of the simulation Data). Declared and
// documented in endovascular_sim/mechanics/device_state.h.
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {

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
