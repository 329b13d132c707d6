// What a hand or a robot feels at the access point: the force and torque
// the drive applies to impose the commanded insertion and rotation.
//
// The drive holds the nodes still in the sheath (introducer.h) on their
// prescribed poses. The elements among them carry no net load to the drive
// (each element's nodal forces balance), so the drive's wrench is the one
// that balances the first element leaving the sheath at the last held node:
// F = dE/dx_k, M = dE/dtheta_k of that element (elastic forces; the held
// part's inertia and the element's Rayleigh damping are left out, small at
// steady insertion). The introducer valve's friction (DriveSpec) is added
// by the step, which knows the drive's motion.
#pragma once

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "endovascular_sim/mechanics/introducer.h"

namespace evsim {

struct DriveWrench {
  Vec3 force{Vec3::Zero()};   // [N] on the device, world
  Vec3 moment{Vec3::Zero()};  // [N m] on the device at the last held node, world
  double axial_force{0.0};    // [N] along the insertion axis: > 0 pushing in (resisted)
  double axial_torque{0.0};   // [N m] about the insertion axis, in the rotation's sense
};

/// The drive's wrench in `state` (zero for a released device or one with
/// every node held or none).
DriveWrench driveWrench(const DeviceModel& model, const Introducer& introducer,
                        const DeviceState& state);

/// A first-order low-pass of a drive's wrench, as a force sensor's filter:
/// y += a (x - y) per sample, a = 1 - exp(-2 pi f_c dt), the exact step
/// response of an RC filter of cutoff f_c sampled every dt (y reaches
/// 1 - 1/e of a step after 1 / (2 pi f_c)). The first sample sets y.
class WrenchLowPass {
 public:
  /// cutoff [Hz] > 0.
  explicit WrenchLowPass(double cutoff_hz) : cutoff_hz_(cutoff_hz) {}
  /// Filters one sample taken dt [s] after the last.
  const DriveWrench& update(const DriveWrench& sample, double dt);
  const DriveWrench& value() const { return y_; }

 private:
  double cutoff_hz_;
  bool primed_{false};
  DriveWrench y_;
};

}  // namespace evsim
