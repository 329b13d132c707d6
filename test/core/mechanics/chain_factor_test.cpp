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
    // Right-hand sides zero on their first blocks: solved from the first
    // nonzero one, the same numbers.
    MatX Z = B;
    Z.topRows(6 * 20).setZero();
    MatX from_zero, from_first = Z;
    f.solve(Z, &from_zero);
    f.solveInPlace(&from_first, 20);
    EXPECT_EQ(from_first, from_zero) << first;
    SparseCholesky chol;
    ASSERT_TRUE(test::factorChain(A, first, &chol));
    MatX Y;
    chol.solve(B, &Y);
    EXPECT_LT((X - Y).norm(), 1e-12 * Y.norm()) << first;
  }
}

// A + C with C on the trailing blocks only (the wall's curvature term on a
// wire touching the wall near its tip): the factor that copies A's pivots
// before C solves like a dense Cholesky of A + C, and gives the numbers a
// factorisation of A + C from scratch gives, to the last bit.
TEST(ChainFactor, ReusesTheFactorOfAMatrixThatSharesItsLeadingBlocks) {
  std::mt19937 rng(5);
  const int blocks = 40;
  for (int first : {0, 3}) {
    for (int changed_from : {first, first + 1, 17, blocks - 1}) {
      const ChainMatrix A = test::randomSpdChain(blocks, &rng);
      ChainMatrix AC = A;
      const ChainMatrix C = test::randomSpdChain(blocks, &rng);  // its trailing part: PSD
      for (int i = changed_from; i < blocks; ++i) {
        AC.diag[i] += C.diag[i];
        if (i + 1 < blocks) AC.upper[i] += C.upper[i];
      }
      ChainFactor of_A, reused, scratch;
      ASSERT_TRUE(of_A.factorize(A, first));
      ASSERT_TRUE(reused.factorize(AC, first, &of_A, changed_from - first));
      ASSERT_TRUE(scratch.factorize(AC, first));
      const int n = 6 * (blocks - first);
      const MatX B = MatX::Random(n, 3);
      MatX X, Y;
      reused.solve(B, &X);
      scratch.solve(B, &Y);
      const MatX reference = AC.toDense().bottomRightCorner(n, n).llt().solve(B);
      EXPECT_LT((X - reference).norm(), 1e-12 * reference.norm()) << first << " " << changed_from;
      EXPECT_EQ(X, Y) << first << " " << changed_from;
      // A prefix claimed longer than the chain is cut to it.
      ChainFactor clamped;
      ASSERT_TRUE(clamped.factorize(A, first, &of_A, 1000));
      clamped.solve(B, &X);
      of_A.solve(B, &Y);
      EXPECT_EQ(X, Y);
    }
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
