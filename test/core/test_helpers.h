// Shared fixtures for the core tests.
#pragma once

#include <random>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/beam_section.h"
#include "endovascular_sim/mechanics/chain_matrix.h"
#include "endovascular_sim/mechanics/so3.h"
#include "endovascular_sim/mechanics/sparse_cholesky.h"

namespace evsim::test {

/// Solid wire: E [Pa], Poisson 0.3, radius [m], density [kg/m^3].
inline BeamSection wireSection(double young_modulus, double radius, double density = 6500.0) {
  BeamSection s;
  s.young_modulus = young_modulus;
  s.shear_modulus = young_modulus / (2.0 * 1.3);
  s.outer_radius = radius;
  s.density = density;
  return s;
}

inline Mat3 randomRotation(std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return expSO3(Vec3(n(*rng), n(*rng), n(*rng)));
}

/// A random symmetric positive definite chain matrix (diagonally dominant
/// 6x6 blocks).
inline ChainMatrix randomSpdChain(int blocks, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  ChainMatrix A;
  A.resize(blocks);
  for (int i = 0; i < blocks; ++i) {
    Mat6 g;
    for (int k = 0; k < 36; ++k) g.data()[k] = n(*rng);
    A.diag[i] = g * g.transpose() + 20.0 * Mat6::Identity();
    if (i + 1 < blocks)
      for (int k = 0; k < 36; ++k) A.upper[i].data()[k] = n(*rng);
  }
  return A;
}

/// CHOLMOD factor of blocks [first, N) of A, as the free motion makes it;
/// false when that part is not positive definite.
inline bool factorChain(const ChainMatrix& A, int first, SparseCholesky* chol) {
  ChainCscPattern pattern;
  pattern.build(A.numBlocks(), first);
  chol->analyze(pattern.size, pattern.col_ptr, pattern.row_idx);
  std::vector<double> values;
  pattern.gather(A, &values);
  return chol->factorize(values);
}

}  // namespace evsim::test
