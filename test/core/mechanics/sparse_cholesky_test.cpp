// CHOLMOD on a chain matrix against Eigen's dense Cholesky.
#include "endovascular_sim/mechanics/sparse_cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "endovascular_sim/mechanics/chain_matrix.h"
#include "test_helpers.h"

namespace evsim {
namespace {

using test::randomSpdChain;

TEST(SparseCholesky, BlockRightHandSidesMatchDenseSolve) {
  std::mt19937 rng(5);
  const ChainMatrix A = randomSpdChain(40, &rng);
  for (int first : {0, 7}) {
    SparseCholesky chol;
    ASSERT_TRUE(test::factorChain(A, first, &chol));
    const int n = chol.size();
    const MatX dense = A.toDense().bottomRightCorner(n, n);
    const MatX B = MatX::Random(n, 5);
    MatX X;
    chol.solve(B, &X);
    const MatX ref = dense.llt().solve(B);
    EXPECT_LT((X - ref).norm(), 1e-12 * ref.norm());
    VecX x = B.col(2);
    chol.solveInPlace(&x);
    EXPECT_LT((x - ref.col(2)).norm(), 1e-12 * ref.norm());
  }
}

TEST(SparseCholesky, ReportsIndefiniteMatrix) {
  std::mt19937 rng(9);
  ChainMatrix A = randomSpdChain(5, &rng);
  A.diag[3](2, 2) = -100.0;
  SparseCholesky chol;
  EXPECT_FALSE(test::factorChain(A, 0, &chol));
}

TEST(ChainMatrix, MultiplyMatchesDense) {
  std::mt19937 rng(2);
  const ChainMatrix A = randomSpdChain(8, &rng);
  const VecX x = VecX::Random(48);
  EXPECT_LT((A.multiply(x) - A.toDense() * x).norm(), 1e-12);
}

}  // namespace
}  // namespace evsim
