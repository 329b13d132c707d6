// Free motion of a device over one time step, linearised implicit Euler:
//   A dq = f_ext - f_int(q) + M v / dt,   A = M/dt^2 + D/dt + K(q),
//   D = alpha M + beta K (Rayleigh damping),  v_next = dq / dt,
// with the held (introducer) nodes prescribed. A is assembled every step
// and factorised as a chain (block LDL^T, mechanics/chain_factor.h); the
// factor stays in the workspace so that the contact solver can solve with A
// again.
#pragma once

#include <vector>

#include "endovascular_sim/core/stage_timer.h"
#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/chain_inverse.h"
#include "endovascular_sim/mechanics/chain_matrix.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "endovascular_sim/mechanics/introducer.h"

namespace evsim {

/// Per-device workspace of a step (Data).
struct DeviceWorkspace {
  ChainMatrix stiffness;      // K of the elements with a free node (held nodes' blocks stale)
  ChainMatrix system;         // A over all nodes (zero before the last held node)
  VecX elastic_gradient;      // f_int of the same (6 * num_nodes; held nodes' entries stale)
  VecX rhs;                   // right-hand side over the free nodes
  VecX dq;                    // free-motion increment of all nodes (6 * num_nodes)
  int first_free_node{-1};    // nodes [0, first_free_node) are held
  ChainFactor factor;         // block LDL^T of A over the free nodes
  ChainMatrix curved_system;  // A + C (the contact solver's wall curvature)
  ChainFactor curved;         // its block LDL^T over the free nodes
  ChainInverse inverse;       // band of A^-1 or (A + C)^-1 (the Delassus operator)
  MatX delassus_storage;      // the contact solver's W between steps (its DelassusBuffer's storage,
                              // kept so that no step allocates and faults it in again)
  double elastic_energy{0.0};  // [J] at the start of the step, of the elements with a free node
};

/// Wall time of each stage [ms], added to by every free motion computed.
struct FreeMotionTimes {
  double assembly_ms{0.0};
  double factorization_ms{0.0};
  double solve_ms{0.0};
};

/// Computes ws->dq for the state's inserted length and rotation angle
/// (already advanced by the drive). With `sheath_hold`, the sheath holds
/// the element leaving it (sheath_support.h); a device inside another is
/// held there by its outer device's lumen instead. Returns false when A is
/// not positive definite (the state is then left untouched by the caller).
/// The stages' times are added to *times, measured on *timer when given
/// (the step's clock: the time before the assembly goes to its remainder).
bool computeFreeMotion(const DeviceModel& model, const Introducer& intro, const Vec3& gravity,
                       double dt, const DeviceState& state, DeviceWorkspace* ws,
                       FreeMotionTimes* times = nullptr, StageTimer* timer = nullptr,
                       bool sheath_hold = true);

/// Applies dq (all nodes) and sets velocities to dq / dt.
void commitMotion(const VecX& dq, double dt, DeviceState* state);

/// Sets velocities to dq / dt (commitMotion's second half, for a state that
/// already holds its positions and rotations moved by dq).
void setStepVelocities(const VecX& dq, double dt, DeviceState* state);

/// Lumped mass block of a node in the world frame (6 x 6).
Mat6 nodeMass(const DeviceModel& model, const DeviceState& state, int node);

}  // namespace evsim
