// The effects a scene names: the one form every layer reads (the contact
// layer through ContactProblem::effects, the step through SceneModel).
#pragma once

namespace evsim {

/// Effects switched on by the scene. An effect that is off costs nothing: its
/// code is never entered (EffectCounters proves it) and nothing is allocated
/// for it.
struct EffectSet {
  bool gravity{false};             // the weight of every node in the free motion
  bool vessel_motion{false};       // the motion regions of the vessels
  bool device_contact{false};      // pairs of device points (devices, a coil with itself)
  bool subdivision{false};         // an unsolved step is redone as halves
  bool friction{false};            // Coulomb friction on every contact (mu per device section)
  bool coaxial{false};             // inner devices held in their outer devices' lumens
  bool blood_drag{false};          // the still blood's viscous drag on every free node
  bool vessel_deformation{false};  // the wall gives way under the devices (geometry/vessel_wall.h)
};

}  // namespace evsim
