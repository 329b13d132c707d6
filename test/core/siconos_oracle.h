// Siconos numerics' LCP solvers, the independent oracle of the LCP tests
// (and a peer in the benchmarks). Test-only: the core does not link Siconos.
#pragma once

#include <siconos/numerics/FrictionContactProblem.h>
#include <siconos/numerics/Friction_cst.h>
#include <siconos/numerics/LCP_Solvers.h>
#include <siconos/numerics/LinearComplementarityProblem.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/lcp_cst.h>

#include <cstring>

#include "endovascular_sim/core/types.h"

namespace evsim::test {

/// Solves with a Siconos LCP solver (e.g. SICONOS_LCP_LEMKE); returns its info
/// (0: success).
inline int siconosLcp(const MatX& W, const VecX& q, int solver, double tolerance, VecX* z,
                      int max_iterations = 100000) {
  const int c = static_cast<int>(q.size());
  NumericsMatrix* M = NM_create(NM_DENSE, c, c);
  std::memcpy(M->matrix0, W.data(), sizeof(double) * c * c);
  VecX qq = q;
  LinearComplementarityProblem problem;
  problem.size = c;
  problem.M = M;
  problem.q = qq.data();
  SolverOptions* options = solver_options_create(solver);
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iterations;
  z->setZero(c);
  VecX w = VecX::Zero(c);
  const int info = linearComplementarity_driver(&problem, z->data(), w.data(), options);
  solver_options_delete(options);
  NM_free(M);
  return info;
}

/// Solves a 3D friction-contact problem (u = W r + q, contact-wise (n, t1,
/// t2)) with a Siconos fc3d solver (e.g. SICONOS_FRICTION_3D_NSN_AC);
/// returns its info (0: success).
inline int siconosFrictionContact(const MatX& W, const VecX& q, const VecX& mu, int solver,
                                  double tolerance, VecX* r, int max_iterations = 100000) {
  const int n = static_cast<int>(q.size());
  NumericsMatrix* M = NM_create(NM_DENSE, n, n);
  std::memcpy(M->matrix0, W.data(), sizeof(double) * n * n);
  VecX qq = q, mm = mu;
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.numberOfContacts = static_cast<int>(mu.size());
  problem.M = M;
  problem.q = qq.data();
  problem.mu = mm.data();
  SolverOptions* options = solver_options_create(solver);
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iterations;
  r->setZero(n);
  VecX u = VecX::Zero(n);
  const int info = fc3d_driver(&problem, r->data(), u.data(), options);
  solver_options_delete(options);
  NM_free(M);
  return info;
}

}  // namespace evsim::test
