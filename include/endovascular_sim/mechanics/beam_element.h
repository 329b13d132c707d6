// Co-rotational Timoshenko beam element with two 6-DOF nodes.
//
// The element frame is the mid-rotation of its nodal frames,
//   Phi = log(R1^T R2),  Rm = R1 exp(Phi / 2),
// and the deformation is measured in it (linear Timoshenko law, one-point
// quadrature, which is free of shear locking):
//   stretch/shear  Gamma = Rm^T (x2 - x1) / L0        (1 + axial strain, shears)
//   twist/bending  kappa = Phi / L0                   [1/m]
//   energy E = L0/2 [(Gamma-Gamma0)^T Cg (Gamma-Gamma0) + (kappa-kappa0)^T Ck (kappa-kappa0)].
// Rigid motions leave Gamma and kappa unchanged, so they cost no energy at any
// rotation; the rest values Gamma0, kappa0 give pre-shaped devices.
// Generalised coordinates of the variation: (dx1, dtheta1, dx2, dtheta2), with
// rotations perturbed on the left in the world frame. The gradient is exact;
// the tangent stiffness is the Gauss-Newton part L0 J^T C J (symmetric,
// positive semi-definite, exact at rest).
#pragma once

#include "endovascular_sim/core/types.h"

namespace evsim {

struct BeamElementRest {
  double length{0.0};                           // L0 [m]
  Vec3 stretch_shear{1.0, 0.0, 0.0};            // Gamma0 [-]
  Vec3 curvature{0.0, 0.0, 0.0};                // kappa0 (twist, bend y, bend z) [1/m]
  Vec3 stretch_shear_stiffness{0.0, 0.0, 0.0};  // (EA, kGA, kGA) [N]
  Vec3 bend_twist_stiffness{0.0, 0.0, 0.0};     // (GJ, EI, EI) [N m^2]
};

struct BeamElementEval {
  Vec6 strain;       // (Gamma - Gamma0, kappa - kappa0)
  double energy{0};  // [J]
  Vec12 gradient;    // dE/dq: forces [N] and world moments [N m] on the nodes
  Mat12 stiffness;   // Gauss-Newton tangent [N/m, N, N m/rad]
};

/// Evaluates energy and gradient, and the tangent when with_stiffness, from
/// the nodal frames as unit quaternions (the state's own form: the element
/// then needs one atan2 and no other trigonometric function).
void evaluateBeamElement(const BeamElementRest& rest, const Vec3& x1, const Quat& q1,
                         const Vec3& x2, const Quat& q2, bool with_stiffness, BeamElementEval* out);
/// The same from rotation matrices.
void evaluateBeamElement(const BeamElementRest& rest, const Vec3& x1, const Mat3& R1,
                         const Vec3& x2, const Mat3& R2, bool with_stiffness, BeamElementEval* out);

/// Consistent tangent (Gauss-Newton part plus geometric stiffness), by
/// central differences of the exact gradient, symmetrised. Costs 24 gradient
/// evaluations: for static solves, where the geometric stiffness matters
/// (P-delta effect); the dynamic step uses the Gauss-Newton tangent.
Mat12 beamElementConsistentTangent(const BeamElementRest& rest, const Vec3& x1, const Mat3& R1,
                                   const Vec3& x2, const Mat3& R2);

/// Rest values of an element whose rest nodal poses are given.
void setBeamElementRestShape(const Vec3& x1, const Mat3& R1, const Vec3& x2, const Mat3& R2,
                             double rest_length, BeamElementRest* rest);

}  // namespace evsim
