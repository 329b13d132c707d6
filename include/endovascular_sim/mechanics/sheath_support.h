// The introducer sheath's hold on the element that is leaving it.
//
// Material with s <= s_a = length - inserted_length is in the sheath, held
// straight on its axis; the nodes there are prescribed (introducer.h). The
// element (k, k + 1) that straddles the access point has the fraction
// f = (s_a - s_k) / L of its length still in the sheath, where the axis is
// straight: the beam is clamped at s_a, not at node k. Held at node k only,
// node k + 1 would be released all at once when s_a passes it: the moment
// and shear the sheath carried jump onto a free node, which springs across
// the axis in one step (a steel pusher's 2 mm elements: 0.2-0.5 mm, and a
// drive force of tens of newtons for that step).
//
// The element's axis is taken as the cubic Hermite curve of its end nodes,
// p(u) = h00 p_k + h10 L t_k + h01 p_k+1 + h11 L t_k+1; node k lies on the
// axis along it, so the deviation from the axis at u = f and its slope are
//   g0 = h01(f) P (p_k+1 - a) + h11(f) L P t_k+1             [m]
//   g1 = h01'(f) / L P (p_k+1 - a) + h11'(f) P t_k+1         [-]
// (P projects across the axis, a the access point). A cubic cannot hold
// both at zero unless node k + 1 is clamped too, so the hold is a penalty,
// E = k0 |g0|^2 / 2 + k1 |g1|^2 / 2 with k0 = c 12 EI / L^3 and
// k1 = c 4 EI / L (the element's own clamped stiffnesses times c): at f -> 1
// (the node just released) it holds the node as the sheath did, and it
// fades as f^4 toward f = 0, where the clamp is at node k. A stiffness,
// not a constraint: it enters A and the free motion's right-hand side of
// the node, and no contact row.
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "endovascular_sim/mechanics/introducer.h"

namespace evsim {

/// The hold's stiffness as a multiple c of the element's clamped stiffness.
constexpr double kSheathHoldFactor = 100.0;

struct SheathHold {
  int node{-1};                 // the first free node it acts on (-1: none)
  double fraction{0.0};         // f: the part of the element (node - 1, node) still in the sheath
  double energy{0.0};           // [J]
  Vec6 gradient{Vec6::Zero()};  // dE/dq of the node: force [N] and world moment [N m]
  Mat6 hessian{Mat6::Zero()};   // its Gauss-Newton tangent
};

/// The sheath's hold on the first free node after `held` (the last held
/// node) in `state`; none when the device is released, the element is cut
/// (a detached coil) or no node is free.
SheathHold sheathHold(const DeviceModel& model, const Introducer& intro, const DeviceState& state,
                      int held);

}  // namespace evsim
