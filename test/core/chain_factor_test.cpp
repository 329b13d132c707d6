// The chain's block LDL^T (mechanics/chain_factor.h) against a dense
// Cholesky solve and against CHOLMOD.
#include "endovascular_sim/mechanics/chain_factor.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "test_helpers.h"

namespace evsim {
namespace {

TEST(ChainFactor, SolvesLikeADenseCholeskyAndLikeCholmod) {
  std::mt19937 rng(3);
  for (int first : {0, 1, 7}) {
    const ChainMatrix A = test::randomSpdChain(60, &rng);
    const int n = 6 * (60 - first);
    ChainFactor f;
    ASSERT_TRUE(f.factorize(A, first));
    EXPECT_EQ(f.size(), n);
    const MatX dense = A.toDense().bottomRightCorner(n, n);
    const MatX B = MatX::Random(n, 5);
    MatX X;
    f.solve(B, &X);
    const MatX reference = dense.llt().solve(B);
    EXPECT_LT((X - reference).norm(), 1e-12 * reference.norm()) << first;
    VecX x = B.col(2);
    f.solveInPlace(&x);
    EXPECT_LT((x - reference.col(2)).norm(), 1e-12 * reference.col(2).norm()) << first;
    SparseCholesky chol;
    ASSERT_TRUE(test::factorChain(A, first, &chol));
    MatX Y;
    chol.solve(B, &Y);
    EXPECT_LT((X - Y).norm(), 1e-12 * Y.norm()) << first;
  }
}

TEST(ChainFactor, ReportsAMatrixThatIsNotPositiveDefinite) {
  std::mt19937 rng(4);
  ChainMatrix A = test::randomSpdChain(20, &rng);
  A.diag[12] = -A.diag[12];
  ChainFactor f;
  EXPECT_FALSE(f.factorize(A, 0));
  EXPECT_TRUE(f.factorize(A, 13));  // the trailing blocks alone are fine
}

}  // namespace
}  // namespace evsim
