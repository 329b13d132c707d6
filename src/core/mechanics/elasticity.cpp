// Elastic energy, forces and tangent stiffness of a whole device. Declared and
// documented in endovascular_sim/mechanics/elasticity.h.
#include "endovascular_sim/mechanics/elasticity.h"

#include <algorithm>

#include "endovascular_sim/mechanics/beam_element.h"
#include "endovascular_sim/mechanics/so3.h"

namespace evsim {

double assembleElasticity(const DeviceModel& model, const DeviceState& state, VecX* gradient,
                          ChainMatrix* K, Tangent tangent, int first_element) {
  const int n = model.num_nodes;
  const int first = std::clamp(first_element, 0, n);
  if (gradient) {  // zero from the first element's first node on
    if (gradient->size() != 6 * n) gradient->setZero(6 * n);
    gradient->tail(6 * (n - first)).setZero();
  }
  if (K) {
    if (K->numBlocks() != n) {
      K->resize(n);
      K->setZero();
    }
    for (int i = first; i < n; ++i) {
      K->diag[i].setZero();
      if (i + 1 < n) K->upper[i].setZero();
    }
  }
  double energy = 0.0;
  BeamElementEval ev;
  for (int e = first; e + 1 < n; ++e) {
    if (e == state.cut_element) continue;  // detached: pusher and coil no longer joined
    evaluateBeamElement(model.elements[e], state.position[e], state.rotation[e],
                        state.position[e + 1], state.rotation[e + 1], K != nullptr, &ev);
    energy += ev.energy;
    if (gradient) gradient->segment<12>(6 * e) += ev.gradient;
    if (K && tangent == Tangent::kConsistent)
      ev.stiffness = beamElementConsistentTangent(
          model.elements[e], state.position[e], state.rotation[e].toRotationMatrix(),
          state.position[e + 1], state.rotation[e + 1].toRotationMatrix());
    if (K) {
      K->diag[e] += ev.stiffness.block<6, 6>(0, 0);
      K->diag[e + 1] += ev.stiffness.block<6, 6>(6, 6);
      K->upper[e] += ev.stiffness.block<6, 6>(0, 6);
    }
  }
  return energy;
}

double elasticEnergy(const DeviceModel& model, const DeviceState& state) {
  return assembleElasticity(model, state, nullptr, nullptr);
}

void applyIncrement(const VecX& dq, int first_node, DeviceState* state) {
  const int n = static_cast<int>(state->position.size());
  for (int i = first_node; i < n; ++i) {
    const int k = 6 * (i - first_node);
    state->position[i] += dq.segment<3>(k);
    state->rotation[i] = expQuaternion(dq.segment<3>(k + 3)) * state->rotation[i];
    state->rotation[i].normalize();
  }
}

}  // namespace evsim
