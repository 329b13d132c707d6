// The still blood's drag on a device (effect 'blood_drag'; not in the
// paper). Across its axis a device meets the drag of a circular cylinder in
// cross-flow, whose coefficient over the Reynolds number Re = rho v d / mu
// (d = 2a the diameter) is, per F. M. White, "Viscous Fluid Flow" (2nd ed.,
// 1991, eq. 3-225; 1 <= Re <= 2e5),
//   C_D(Re) = 1 + 10 Re^(-2/3),   force per unit length 1/2 rho d C_D v^2:
// viscous at Re near one (a wire pushed at 10 mm/s), mostly form drag at
// the hundreds a coil's turns reach as they spring across a dome (3 m/s).
// Below, where the whole device is in Stokes flow, slender-body theory's
// drag of a rod of length L (R. G. Cox, "The motion of long slender bodies
// in a viscous fluid. Part 1. General theory", J. Fluid Mech. 44, 1970, the
// leading term in 1 / ln(L / a)) is the floor:
//   c_across = 4 pi mu / ln(L / a),   c_along = 2 pi mu / ln(L / a)
// [N s / m^2]. Along the axis the drag is skin friction only, Cox's. Each
// node carries the drag of its half of the two elements beside it; the free
// motion takes it implicitly with the coefficient at the node's velocity at
// the step's start (A += D(v_t) / dt, docs/model.md). The blood is at rest
// in the world frame: no flow, and vessels that move do not carry it.
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/device_model.h"

namespace evsim {

/// The still blood (scene keys blood_viscosity and blood_density).
struct Blood {
  double viscosity{3.5e-3};  // [Pa s]
  double density{1060.0};    // [kg/m^3]
};

/// Slender-body drag coefficients per unit length [N s / m^2] of a rod of
/// length L [m] and radius a [m] in a fluid of viscosity mu [Pa s] (ln(L /
/// a) taken as at least 1: a rod that is not slender gets a bounded drag).
double dragAcross(double mu, double L, double a);
double dragAlong(double mu, double L, double a);

/// A circular cylinder's drag coefficient in cross-flow at Reynolds number
/// re > 0 (White's fit: 1 + 10 re^(-2/3)).
double cylinderDragCoefficient(double re);

/// The drag across the axis per unit length and unit speed [N s / m^2] of
/// a rod of length L [m] and radius a [m] moving across its axis at
/// `speed` [m/s]: the larger of the cylinder's 1/2 rho d C_D(Re) speed and
/// Cox's c_across.
double dragAcrossAt(const Blood& blood, double L, double a, double speed);

/// Sets the model's per-node drag (node_drag_across, _along, _form,
/// _reynolds) for the blood.
void setBloodDrag(const Blood& blood, DeviceModel* model);

/// The damping matrix [N s / m] of node i whose axis is the unit `tangent`
/// and whose velocity is `velocity` [m/s] (the coefficient across the axis
/// at the speed across it).
Mat3 nodeDrag(const DeviceModel& model, int i, const Vec3& tangent, const Vec3& velocity);

}  // namespace evsim
