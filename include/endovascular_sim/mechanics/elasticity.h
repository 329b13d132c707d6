// Elastic energy, forces and tangent stiffness of a whole device.
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/chain_matrix.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {

enum class Tangent { kGaussNewton, kConsistent };

/// Sums the elements: gradient (6 * num_nodes: force [N], moment [N m] per
/// node) and, when K is not null, the tangent. Returns energy [J].
double assembleElasticity(const DeviceModel& model, const DeviceState& state, VecX* gradient,
                          ChainMatrix* K, Tangent tangent = Tangent::kGaussNewton);

/// Elastic energy alone [J].
double elasticEnergy(const DeviceModel& model, const DeviceState& state);

/// Applies generalised increments dq (6 per node: dx [m], world dtheta [rad])
/// to nodes [first_node, num_nodes); dq holds those nodes only.
void applyIncrement(const VecX& dq, int first_node, DeviceState* state);

}  // namespace evsim
