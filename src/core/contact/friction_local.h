// Pieces shared by the friction solvers (friction.cpp, friction_newton.cpp):
// the cone, each contact's exact local solution and the Gauss-Seidel sweep
// built on it. Internal to the core library.
#pragma once

#include <vector>

#include "endovascular_sim/contact/friction.h"

namespace evsim {
namespace friction {

/// Projection on the cone |r_t| <= mu r_n.
Vec3 projectOnCone(const Vec3& r, double mu);

/// One Gauss-Seidel sweep: each contact's exact solution of its 3 x 3
/// problem with the others' forces fixed. `block` holds the diagonal blocks
/// of W (regularised).
void gaussSeidelSweep(const MatXView& W, const VecX& q, const VecX& mu,
                      const std::vector<Mat3>& block, VecX* r);

/// frictionResidual with the velocities u = W r + q already known.
double residualAt(const VecX& q, const VecX& mu, const VecX& r, const VecX& u);

/// The Newton solver (friction_newton.cpp): at most max_steps steps from r;
/// adds its steps to stats->sweeps and leaves the last residual there.
LcpStatus solveNewton(const MatXView& W, const VecX& q, const VecX& mu,
                      const std::vector<Mat3>& block, double eps, int max_steps, double tolerance,
                      VecX* r, FrictionStats* stats);

}  // namespace friction
}  // namespace evsim
