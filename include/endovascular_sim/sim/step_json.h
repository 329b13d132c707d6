// One JSON object per simulation step: `evsim run --json`, and the Python
// front's step statistics (the same names and units). Every JSON line the
// project prints goes through jsonLine: valid JSON whatever its strings hold.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "endovascular_sim/sim/autopilot.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// An object as one line of JSON: strings escaped (invalid UTF-8 replaced),
/// numbers in the shortest form that reads back to the same double, a
/// non-finite number as null.
std::string jsonLine(const nlohmann::ordered_json& object);

/// {"step", "t" [s], "wall_ms", "contacts", "max_penetration_m", stage times,
///  "devices": [{"name", "tip" [m, xyz], "inserted_m", "rotation_rad", "kinetic_energy_J",
///               with vessels "tip_vessel", "tip_depth_m", "tip_in_lumen"}],
///  with targets "targets": [{"vessel", "reached", "reached_time" [s], "best_depth_m"}]}
std::string stepJson(const SceneModel& model, const SimData& data);

/// The autopilot's summary (`evsim navigate`): {"scene", "target", "device",
/// "reached", "reason", "time_s", "retries", "peak_wall_force_N",
/// "failed_steps", "remaining_path_m", "final_vessel"}; `target` a vessel
/// and `device` the lead device of the run that ended with `report`.
std::string autopilotJson(const SceneModel& model, const SimData& data, int target, int device,
                          const AutopilotReport& report);

}  // namespace evsim
