// One JSON object per simulation step: `evsim run --json`, and the Python
// front's step statistics (the same names and units).
#pragma once

#include <string>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// {"step", "t" [s], "wall_ms", "contacts", "max_penetration_m", stage times,
///  "devices": [{"name", "tip" [m, xyz], "inserted_m", "rotation_rad", "kinetic_energy_J",
///               with vessels "tip_vessel", "tip_depth_m", "tip_in_lumen"}],
///  with targets "targets": [{"vessel", "reached", "reached_time" [s], "best_depth_m"}]}
std::string stepJson(const SceneModel& model, const SimData& data);

}  // namespace evsim
