// The wall's curvature in the step's system matrix (a sequential-QP step).
//
// A contact's plane is the wall linearised at one point. A point sliding
// along that plane on a wall that curves around it (inside a tube) goes
// beyond the wall by s^2 kappa / 2, which no plane sees; a squeezed, nearly
// free mode (a J-tip rolling about the tube's axis) then slides far in
// every loop and each new plane leaves it a few um beyond the wall again.
// The Lagrangian of the step, E(x) - sum lambda_i phi_i(p_i(x)) with phi the
// signed distance to the wall, has the Hessian A - sum lambda_i J_i^T
// Hess(phi_i) J_i: for a wall curving around the point, -Hess(phi) in the
// tangent plane is the positive curvature tensor S, a stiffness lambda S
// [N/m] against sliding. Each activation loop adds
//   C = sum_i lambda_i J_i^T T_i S_i+ T_i^T J_i
// (S+ the positive part, T_i the tangent basis, J_i the 3 x 12 Jacobian of
// the point over its element's two nodes, lambda_i the last loop's force)
// to A and solves the QP step about the last iterate x_k:
//   (A + C) dq = A dq_free + C dq_k,   W = H (A + C)^-1 H^T.
// With C = 0 this is the paper's step.
//
// The first loop takes its QP about x_t (dq_k = 0), later loops about the
// last iterate. The loop ends once no point is beyond the wall, which may
// come before dq = dq_k; what is left, C (dq - dq_k), is then a stiffness
// against sliding from where the step began: a spring released every step,
// it only dissipates, and a resting device stays at rest. About x_f it
// pulled each point toward where its inertia carried it and fed a 100 Hz
// limit cycle of a wire at rest in the carotid scene (20 um per step;
// Stability.AWireAtRestStaysAtRest).
#pragma once

#include <array>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/implicit_surface.h"

namespace evsim {

/// Positive part of the wall's curvature tensor [1/m] at a surface point in
/// the tangent basis t (the columns are returned in *t): S = -T^T Hess(g) T
/// / |grad g| by central differences of the gradient (step h [m]),
/// eigenvalues clamped at 0 (a wall curving away from the point adds
/// nothing).
Eigen::Matrix2d wallCurvature(const ImplicitSurface& surface, const Vec3& point, const Vec3& normal,
                              double device_radius, const MotionSnapshot& motion,
                              std::array<Vec3, 2>* t, double h = 1e-5);

}  // namespace evsim
