// A batch of simulations stepped from an array of drive commands by a pool
// of threads, as MuJoCo's rollout: what a learning agent's vectorised
// environment and a sweep of controllers need, with the loop in C++.
//
// Simulation n (its own SimData, of its own SceneModel) holds command
// commands[n][t] for `steps_per_command` steps, for t = 0 .. T-1; after each
// command's steps the rollout records the devices' state. Each simulation
// is stepped whole by one thread, so the answer is that of the same
// simulations stepped one by one, whatever the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// What a rollout writes per simulation n and command t (row-major arrays).
struct RolloutOutput {
  long batch{0}, horizon{0};  // N and T
  int devices{0};             // devices of each simulation (the same for all)
  int nodes{0};               // nodes of all its devices, in device order
  std::vector<double> time;             // (N x T) [s] after the command's steps
  std::vector<double> node_position;    // (N x T x nodes x 3) [m]
  std::vector<double> tip_position;     // (N x T x devices x 3) [m]
  std::vector<double> inserted_length;  // (N x T x devices) [m]
  std::vector<double> rotation_angle;   // (N x T x devices) [rad]
  std::vector<double> drive_force;       // (N x T x devices) [N] axial, > 0 pushing in (resisted)
  std::vector<double> peak_drive_force;  // (N x T x devices) [N] largest |drive_force| of its steps
  std::vector<int> tip_vessel;           // (N x T x devices) atlas index (-1: no vessels)
  std::vector<double> max_wall_force;    // (N x T) [N] largest wall contact force of its steps
  std::vector<std::int8_t> failed;      // (N x T) 1 from the command whose steps failed on
};

/// Why a batch cannot be rolled out ("" when it can): the models' and
/// data's counts, a command of the wrong width, one not finite or beyond a
/// device's limits (named by its indices). Nothing is stepped when it is
/// not "".
std::string checkRollout(const std::vector<const SceneModel*>& models,
                         const std::vector<SimData*>& data, const double* commands, long horizon,
                         long steps_per_command);

/// Steps the batch: `commands` is (N x T x 2·devices) row-major, per device
/// its insertion velocity [m/s] and rotation velocity [rad/s] (velocity
/// mode). A step the scene cannot solve is retried with the recovery
/// options when `recover` (stepOrRecover); a simulation whose step fails
/// stops there (its data keep the last good state and last_error says
/// why), its later records repeat that state with failed = 1. Threads:
/// at most `threads` (at least 1, at most N). Throws std::invalid_argument
/// with checkRollout's reason.
RolloutOutput rollout(const std::vector<const SceneModel*>& models,
                      const std::vector<SimData*>& data, const double* commands, long horizon,
                      long steps_per_command, int threads, bool recover = true);

}  // namespace evsim
