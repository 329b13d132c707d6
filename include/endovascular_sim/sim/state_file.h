// A simulation's state on disk, to resume a run where it was saved (a late
// failure or a slow phase studied from its step, with other options or
// another build): `evsim run SCENE --load-state F --save-state G`.
//
// Text, one record per line, doubles to 17 significant digits (the state
// comes back bit for bit):
//   evsim_state 4
//   scene <name>
//   clock <time [s]> <step> <next script entry> <resting steps> <asleep 0|1>
//         (version 1 files end after the script entry: read as awake)
//   device <name> <nodes> <inserted length [m]> <rotation angle [rad]> <released 0|1>
//          <cut element>
//   node <position [m] x3> <rotation w x y z> <velocity [m/s] x3> <angular velocity [rad/s] x3>
//   command <mode 0 velocity|1 position> <insertion> <rotation>      (per device)
//   contacts <count>
//   contact <device> <sample> <point x3> <normal x3> <gap> <force> <other device>
//           <other sample> <friction x3> <other element> <xi> <radius> <mu>
//           <separation> <lumen 0|1> <element> <xi> <radius> <mu>
//   wall <points>   (effect 'vessel_deformation': the centreline's points; 0 at rest)
//   wall_point <displacement [m] x3> <radius change [m]>      (per point)
// The contacts are the last step's (the next step's warm start). Only the
// state is saved: the scene comes from its own file, and must be the one
// the state was saved from (its name, devices and node counts are checked).
// Loading copies into the data's own node arrays (views of them stay valid).
#pragma once

#include <string>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// Writes the state of `data` (false when the file cannot be written).
bool saveState(const SceneModel& model, const SimData& data, const std::string& path);

/// The text saveState writes (a pickled simulation carries it).
std::string stateText(const SceneModel& model, const SimData& data);

/// Reads a state saved for `model` into `data`. Throws LoadError naming the
/// file, line and field when it cannot be read, is malformed, non-finite, or
/// belongs to another scene; `data` is then unchanged.
void loadState(const SceneModel& model, const std::string& path, SimData* data);

/// loadState from the text of a state file; errors name `source` as the file.
void loadStateText(const SceneModel& model, const std::string& text, const std::string& source,
                   SimData* data);

}  // namespace evsim
