// Siconos numerics' LCP solvers, the independent oracle of the LCP tests
// (and a peer in the benchmarks). Test-only: the core does not link Siconos.
#pragma once

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

}  // namespace evsim::test
