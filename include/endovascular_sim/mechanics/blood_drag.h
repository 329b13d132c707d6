// The still blood's viscous drag on a device (effect 'blood_drag'; not in
// the paper). A device in a vessel moves at Reynolds numbers of order one
// or below (a 0.25 mm coil at 50 mm/s in blood: 4), where slender-body
// theory gives the drag per unit length as linear in the velocity and twice
// as strong across the axis as along it (R. G. Cox, "The motion of long
// slender bodies in a viscous fluid. Part 1. General theory", J. Fluid
// Mech. 44, 1970, the leading term in 1 / ln(L / a)):
//   c_across = 4 pi mu / ln(L / a),   c_along = 2 pi mu / ln(L / a)
// [N s / m^2], mu the viscosity, L the device's length, a its radius. Each
// node carries the drag of its half of the two elements beside it; the
// free motion takes it implicitly (A += D / dt, docs/model.md). The blood
// is at rest in the world frame: no flow, and vessels that move do not
// carry it.
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"

namespace evsim {

/// Drag coefficients per unit length [N s / m^2] of a rod of length L [m]
/// and radius a [m] in a fluid of viscosity mu [Pa s] (ln(L / a) taken as
/// at least 1: a rod that is not slender gets a bounded drag).
double dragAcross(double mu, double L, double a);
double dragAlong(double mu, double L, double a);

/// Sets model->node_drag_across and node_drag_along [N s / m] for a fluid
/// of viscosity mu [Pa s].
void setBloodDrag(double mu, DeviceModel* model);

/// The damping matrix [N s / m] of node i whose axis is the unit `tangent`.
Mat3 nodeDrag(const DeviceModel& model, int i, const Vec3& tangent);

}  // namespace evsim
