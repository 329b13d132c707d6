// Static equilibrium of a device under nodal loads with its first nodes
// clamped: Newton steps on the exact residual with the consistent tangent
// (Gauss-Newton where that is not positive definite) and load stepping.
// Declared and documented in endovascular_sim/mechanics/static_equilibrium.h.
#include "endovascular_sim/mechanics/static_equilibrium.h"

#include "endovascular_sim/mechanics/chain_matrix.h"
#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/mechanics/sparse_cholesky.h"

namespace evsim {
namespace {

/// Residual over the free nodes: load - elastic gradient.
VecX residual(const DeviceModel& model, const DeviceState& state, const VecX& load, int first,
              ChainMatrix* K, Tangent tangent = Tangent::kConsistent) {
  VecX g;
  assembleElasticity(model, state, &g, K, tangent);
  return load.tail(load.size() - 6 * first) - g.tail(g.size() - 6 * first);
}

}  // namespace

StaticResult solveStaticEquilibrium(const DeviceModel& model, int clamped_nodes,
                                    const std::vector<Vec6>& wrenches, const StaticOptions& options,
                                    DeviceState* state) {
  const int n = model.num_nodes;
  VecX full_load(6 * n);
  for (int i = 0; i < n; ++i) full_load.segment<6>(6 * i) = wrenches[i];
  const double scale = std::max(model.length, 1.0);

  ChainCscPattern pattern;
  pattern.build(n, clamped_nodes);
  SparseCholesky cholesky;
  cholesky.analyze(pattern.size, pattern.col_ptr, pattern.row_idx);
  std::vector<double> values;
  ChainMatrix K;
  StaticResult result;

  for (int step = 1; step <= options.load_steps; ++step) {
    const VecX load = full_load * (static_cast<double>(step) / options.load_steps);
    result.converged = false;
    for (int it = 0; it < options.max_iterations && !result.converged; ++it) {
      const VecX r = residual(model, *state, load, clamped_nodes, &K);
      pattern.gather(K, &values);
      if (!cholesky.factorize(values)) {
        // Not positive definite (the geometric stiffness dominates): use the
        // Gauss-Newton tangent for this iteration.
        residual(model, *state, load, clamped_nodes, &K, Tangent::kGaussNewton);
        pattern.gather(K, &values);
        if (!cholesky.factorize(values)) return result;
      }
      VecX dq = r;
      cholesky.solveInPlace(&dq);
      if (!dq.allFinite()) return result;
      applyIncrement(dq, clamped_nodes, state);
      ++result.iterations;
      result.converged = dq.lpNorm<Eigen::Infinity>() <= options.increment_tolerance * scale;
    }
    if (!result.converged) break;
  }
  result.residual = residual(model, *state, full_load, clamped_nodes, &K).norm();
  return result;
}

}  // namespace evsim
