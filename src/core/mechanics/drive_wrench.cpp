// What a hand or a robot feels at the access point: the force and torque the
// drive applies to impose the commanded insertion and rotation. Declared and
// documented in endovascular_sim/mechanics/drive_wrench.h.
#include "endovascular_sim/mechanics/drive_wrench.h"

#include <algorithm>
#include <cmath>

#include "endovascular_sim/mechanics/beam_element.h"

namespace evsim {

DriveWrench driveWrench(const DeviceModel& model, const Introducer& introducer,
                        const DeviceState& state) {
  DriveWrench w;
  if (state.released) return w;
  int k = lastHeldNode(model, state.inserted_length);
  if (state.cut_element >= 0) k = std::min(k, state.cut_element);    // as computeFreeMotion
  if (k + 1 >= model.num_nodes || k == state.cut_element) return w;  // the cut carries nothing
  BeamElementEval e;
  evaluateBeamElement(model.elements[k], state.position[k], state.rotation[k],
                      state.position[k + 1], state.rotation[k + 1], false, &e);
  w.force = e.gradient.segment<3>(0);
  w.moment = e.gradient.segment<3>(3);
  const Vec3 axis = introducer.frame.col(0);
  w.axial_force = w.force.dot(axis);
  w.axial_torque = w.moment.dot(axis);
  return w;
}

const DriveWrench& WrenchLowPass::update(const DriveWrench& x, double dt) {
  if (!primed_) {
    y_ = x;
    primed_ = true;
    return y_;
  }
  const double a = 1.0 - std::exp(-2.0 * M_PI * cutoff_hz_ * dt);
  y_.force += a * (x.force - y_.force);
  y_.moment += a * (x.moment - y_.moment);
  y_.axial_force += a * (x.axial_force - y_.axial_force);
  y_.axial_torque += a * (x.axial_torque - y_.axial_torque);
  return y_;
}

}  // namespace evsim
