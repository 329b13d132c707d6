// Coulomb friction in the contact space (effect 'friction').
//
// Each contact i has three rows: its normal n and two tangents t1, t2.
// With W the 3c x 3c Delassus operator and q the free gaps (normal rows [m])
// and free slips (tangent rows: displacement of the point along t over the
// step [m]), find r = (r_n, r_t) per contact with u = W r + q and
//   0 <= r_n  _|_  u_n >= 0                       (Signorini)
//   |r_t| <= mu r_n,  u_t != 0  =>  r_t = -mu r_n u_t / |u_t|   (Coulomb)
// — Siconos' 3D friction-contact problem (fc3d), the same law.
//
// Solvers:
//  - kNewton (default), the status method extended to stick and slip: each
//    contact's status (separated, sticking, sliding) selects the branch of
//    the Alart-Curnier function phi(r) = r - P(r - rho u) (P: projection
//    on the cone, rho = 1 / diag W per contact), and Newton's method solves
//    J dr = -phi with the Jacobian of those branches; only the rows of
//    contacts that are not separated are formed and factorised (dense LU).
//    A non-monotone line search on |phi|^2 accepts a step below the largest
//    |phi|^2 of the last 10 iterates; a step it rejects falls back to one
//    Gauss-Seidel sweep. It starts from the better (smaller residual) of the
//    forces given and the frictionless answer (the normal rows' LCP by the
//    status method) and, if that start has not converged after a quarter of
//    the steps, restarts from the other. On the friction problems of
//    `carotid_catheter` it needs 9.4 steps from zero (Siconos' NSN_AC is
//    ~40x slower there); it solves a thread wrapped on a cylinder with
//    contacts between the nodes (cond W ~ 1e17).
//  - kNsgs, the baseline: non-smooth block Gauss-Seidel, a cone-projected
//    solver. Each sweep solves every contact's 3 x 3 problem exactly with
//    the others' forces fixed: separated (b_n >= 0: r = 0), sticking
//    (r = -W_ii^-1 b inside the cone) or sliding (on the cone's boundary:
//    the slip angle found by bracketing and bisection, so anisotropic W_ii
//    is handled exactly). It stalls on redundant contacts (residual 1e-9
//    after 65,000 sweeps on a stiff wire on a plane at tan theta ~ mu;
//    one of the 100 `carotid_catheter` problems unsolved in 20,000). It
//    starts from the forces given (the previous loop's or step's).
#pragma once

#include <string>

#include "endovascular_sim/contact/lcp.h"
#include "endovascular_sim/core/types.h"

namespace evsim {

enum class FrictionSolver { kNewton, kNsgs };

/// "newton", "nsgs" (throws std::invalid_argument otherwise).
FrictionSolver frictionSolverFromName(const std::string& name);
const char* frictionSolverName(FrictionSolver solver);

struct FrictionOptions {
  FrictionSolver solver{FrictionSolver::kNewton};
  double tolerance{1e-10};  // on the natural-map residual (frictionResidual) [-]
  int max_sweeps{1000};     // Newton steps or Gauss-Seidel sweeps
};

struct FrictionStats {
  int sweeps{0};    // Newton steps or Gauss-Seidel sweeps
  int sticking{0};  // contacts with r_n > 0 strictly inside the cone
  int sliding{0};   // contacts with r_n > 0 on the cone's boundary
  double residual{0.0};
};

/// Solves the problem; r (size 3c) is the warm start when it has the right
/// size (zero otherwise) and receives the forces [N]. kIterationLimit when
/// the residual is still above the tolerance after max_sweeps.
LcpStatus solveFrictionalContact(const MatXView& W, const VecX& q, const VecX& mu,
                                 const FrictionOptions& options, VecX* r,
                                 FrictionStats* stats = nullptr);

/// Siconos' fc3d error: sqrt(sum_i |r_i - P_K(r_i - u^_i)|^2) / |q|, with
/// u^_i = u_i + mu |u_t,i| e_n (De Saxce) and P_K the projection on the cone
/// |r_t| <= mu r_n; 0 when q = 0 and r = 0.
double frictionResidual(const MatXView& W, const VecX& q, const VecX& mu, const VecX& r);

}  // namespace evsim
