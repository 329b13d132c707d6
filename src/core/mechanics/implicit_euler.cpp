// Free motion of a device over one time step, linearised implicit Euler.
// Declared and documented in endovascular_sim/mechanics/implicit_euler.h.
#include "endovascular_sim/mechanics/implicit_euler.h"

#include <algorithm>

#include "endovascular_sim/mechanics/blood_drag.h"
#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/mechanics/sheath_support.h"
#include "endovascular_sim/mechanics/so3.h"

namespace evsim {

Mat6 nodeMass(const DeviceModel& model, const DeviceState& state, int node) {
  Mat6 m = Mat6::Zero();
  m.topLeftCorner<3, 3>().diagonal().setConstant(model.node_mass[node]);
  const Mat3 R = state.rotation[node].toRotationMatrix();
  m.bottomRightCorner<3, 3>() = R * model.node_inertia[node].asDiagonal() * R.transpose();
  return m;
}

bool computeFreeMotion(const DeviceModel& model, const Introducer& intro, const Vec3& gravity,
                       double dt, const DeviceState& state, DeviceWorkspace* ws,
                       FreeMotionTimes* times, StageTimer* timer, bool sheath_hold) {
  StageTimer own;
  StageTimer& clock = timer ? *timer : own;
  clock.begin();
  const int n = model.num_nodes;
  int held = state.released ? -1 : lastHeldNode(model, state.inserted_length);
  if (state.cut_element >= 0) held = std::min(held, state.cut_element);  // never the coil's
  const int first_free = held + 1;
  ws->dq.setZero(6 * n);

  // Prescribed increments of the held nodes. Their rotations are alike (one
  // per rest twist, the same increments applied step after step): heldPose's
  // rotation is formed again only where the twist changes, and the turn's
  // log only where the node's rotation differs from its neighbour's (the
  // same numbers as node by node).
  Mat3 R;
  for (int i = 0; i <= held; ++i) {
    const bool new_twist = i == 0 || model.rest_twist[i] != model.rest_twist[i - 1];
    if (new_twist) R = heldRotation(intro, state.rotation_angle, model.rest_twist[i]);
    const Vec3 x = heldPosition(model, intro, state.inserted_length, i);
    ws->dq.segment<3>(6 * i) = x - state.position[i];
    if (!new_twist && state.rotation[i].coeffs() == state.rotation[i - 1].coeffs())
      ws->dq.segment<3>(6 * i + 3) = ws->dq.segment<3>(6 * i - 3);
    else
      ws->dq.segment<3>(6 * i + 3) = logSO3(R * state.rotation[i].toRotationMatrix().transpose());
  }

  // Only the elements with a free node: [held, n - 1) (the element from the
  // last held node couples it to the first free one).
  ws->elastic_energy = assembleElasticity(model, state, &ws->elastic_gradient, &ws->stiffness,
                                          Tangent::kGaussNewton, held);
  const double cm = 1.0 / (dt * dt) + model.rayleigh_mass / dt;
  const double ck = 1.0 + model.rayleigh_stiffness / dt;
  ChainMatrix& A = ws->system;
  A.resize(n);
  const int nf = n - first_free;
  ws->rhs.resize(6 * nf);
  const bool with_gravity = !gravity.isZero(0.0);  // effect 'gravity' off: zero
  for (int i = 0; i < held; ++i) {                 // zero: the factor starts at the first free node
    A.diag[i].setZero();
    A.upper[i].setZero();
  }
  for (int i = std::max(held, 0); i < n; ++i) {
    const Mat6 M = nodeMass(model, state, i);
    A.diag[i] = cm * M + ck * ws->stiffness.diag[i];
    if (!model.node_drag_across.empty())  // effect 'blood_drag': D(v_t) v at the step's end
      A.diag[i].topLeftCorner<3, 3>() +=
          nodeDrag(model, i, state.rotation[i] * Vec3::UnitX(), state.velocity[i]) / dt;
    if (i + 1 < n) A.upper[i] = ck * ws->stiffness.upper[i];
    if (i < first_free) continue;
    Vec6 f = Vec6::Zero();
    if (with_gravity) f.head<3>() = model.node_mass[i] * gravity;
    Vec6 v;
    v << state.velocity[i], state.angular_velocity[i];
    ws->rhs.segment<6>(6 * (i - first_free)) =
        f - ws->elastic_gradient.segment<6>(6 * i) + M * v / dt;
  }
  if (nf > 0 && held >= 0)
    ws->rhs.head<6>() -= A.upper[held].transpose() * ws->dq.segment<6>(6 * held);
  // The sheath's hold on the element leaving it (sheath_support.h).
  const SheathHold hold = sheath_hold ? sheathHold(model, intro, state, held) : SheathHold{};
  if (hold.node >= 0 && nf > 0) {
    A.diag[hold.node] += hold.hessian;
    ws->rhs.head<6>() -= hold.gradient;
  }
  clock.end(times ? &times->assembly_ms : nullptr);

  ws->first_free_node = first_free;
  clock.begin();
  const bool factored = ws->factor.factorize(A, first_free);
  clock.end(times ? &times->factorization_ms : nullptr);
  if (!factored) return false;
  if (nf == 0) return true;

  clock.begin();
  ws->factor.solveInPlace(&ws->rhs);
  ws->dq.tail(6 * nf) = ws->rhs;
  clock.end(times ? &times->solve_ms : nullptr);
  return ws->dq.allFinite();
}

void commitMotion(const VecX& dq, double dt, DeviceState* state) {
  applyIncrement(dq, 0, state);
  setStepVelocities(dq, dt, state);
}

void setStepVelocities(const VecX& dq, double dt, DeviceState* state) {
  const int n = static_cast<int>(state->position.size());
  for (int i = 0; i < n; ++i) {
    state->velocity[i] = dq.segment<3>(6 * i) / dt;
    state->angular_velocity[i] = dq.segment<3>(6 * i + 3) / dt;
  }
}

}  // namespace evsim
