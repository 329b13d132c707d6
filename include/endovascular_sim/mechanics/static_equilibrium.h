// Static equilibrium of a device under nodal loads with its first nodes
// clamped: Newton steps on the exact residual with the consistent tangent
// (Gauss-Newton where that is not positive definite) and load stepping.
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {

struct StaticOptions {
  int load_steps{1};
  int max_iterations{200};            // per load step
  double increment_tolerance{1e-12};  // max |dq| / max(length, 1 m) at convergence
};

struct StaticResult {
  bool converged{false};
  int iterations{0};
  double residual{0.0};  // final |residual| [N, N m]
};

/// Dead loads: wrenches[i] = (force [N], moment [N m]) on node i. Nodes
/// [0, clamped_nodes) keep their pose.
StaticResult solveStaticEquilibrium(const DeviceModel& model, int clamped_nodes,
                                    const std::vector<Vec6>& wrenches, const StaticOptions& options,
                                    DeviceState* state);

}  // namespace evsim
