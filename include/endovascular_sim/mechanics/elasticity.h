// Elastic energy, forces and tangent stiffness of a whole device.
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/chain_matrix.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"

namespace evsim {

enum class Tangent { kGaussNewton, kConsistent };

/// Sums the elements [first_element, num_nodes - 1): gradient (6 *
/// num_nodes: force [N], moment [N m] per node) and, when K is not null,
/// the tangent; the nodes before first_element keep what they held (zero
/// when the vector or matrix is new). Returns their energy [J]. The free motion
/// leaves out the elements whose both nodes the introducer holds: they move
/// with the drive, and nothing of theirs enters the free nodes' system.
double assembleElasticity(const DeviceModel& model, const DeviceState& state, VecX* gradient,
                          ChainMatrix* K, Tangent tangent = Tangent::kGaussNewton,
                          int first_element = 0);

/// Elastic energy alone [J].
double elasticEnergy(const DeviceModel& model, const DeviceState& state);

/// Applies generalised increments dq (6 per node: dx [m], world dtheta [rad])
/// to nodes [first_node, num_nodes); dq holds those nodes only.
void applyIncrement(const VecX& dq, int first_node, DeviceState* state);

}  // namespace evsim
