// Block LDL^T of a symmetric positive definite chain matrix (6x6 block
// tridiagonal, mechanics/chain_matrix.h), over its trailing blocks
// [first, N): the held nodes of a device are left out.
//
//   D_0 = A_00,   L_i = A_{i,i-1} D_{i-1}^-1,   D_i = A_ii - L_i A_{i-1,i}
//
// O(N) 6x6 operations, no fill-in, no pivoting (A is SPD); each pivot D_i
// and its coupling block are eliminated together (Gauss-Jordan on
// [D_i | A_{i,i+1} | I]), about 0.3 us a block (BM_FreeMotionStep): what the
// free motion, the wall-curvature step and the Delassus operator's block
// solves use.
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/chain_matrix.h"

namespace evsim {

class ChainFactor {
 public:
  /// Factorises blocks [first, A.numBlocks()) of A; false when a pivot block
  /// is not positive definite (the factor is then unusable). With `same`, a
  /// factor of another matrix from the same `first` whose blocks (diagonal
  /// and coupling) before first + same_blocks equal A's: the pivots there
  /// are copied from it, not eliminated again (A + C with C on the distal
  /// blocks only). Blocks before first + same_blocks of A are not read.
  bool factorize(const ChainMatrix& A, int first, const ChainFactor* same = nullptr,
                 int same_blocks = 0);
  /// Blocks of the factorised part.
  int numBlocks() const { return static_cast<int>(d_inv_.size()); }
  /// Dimension of the factorised part (6 numBlocks()).
  int size() const { return 6 * numBlocks(); }
  /// -L_{i+1}^T = -D_i^-1 A_{i,i+1}, i in [0, numBlocks() - 1) (relative to first).
  const Mat6& transfer(int i) const { return transfer_[i]; }
  /// D_i^-1.
  const Mat6& pivotInverse(int i) const { return d_inv_[i]; }
  /// b <- A^-1 b (size() entries): forward through L, D^-1, back through
  /// L^T; b's blocks before first_nonzero are zero (the forward pass and
  /// D^-1 start there).
  void solveInPlace(VecX* b, int first_nonzero = 0) const;
  /// X = A^-1 B for a block of right-hand sides (size() x k).
  void solve(const MatX& B, MatX* X) const;
  /// X <- A^-1 X (size() x k), whose blocks before first_nonzero are zero
  /// (the forward pass starts there).
  void solveInPlace(MatX* X, int first_nonzero = 0) const;
  /// The blocks [first, numBlocks()) of A^-1 B for a B whose blocks before
  /// `first` are zero: *X holds B's blocks from `first` on (6 (numBlocks() -
  /// first) x k) and becomes those of the solution, the same numbers as
  /// solveInPlace's there (the blocks before `first` follow from block
  /// `first` through transfer(): x_i = transfer(i) x_{i+1}).
  void solveTrailingInPlace(MatX* X, int first) const;

 private:
  /// D_i^-1 applied in place to a 6-row block of columns, column by column
  /// (no temporary on the heap).
  template <typename Block>
  void applyPivotInverse(int i, Block&& block) const {
    for (Eigen::Index c = 0; c < block.cols(); ++c) {
      const Vec6 y = d_inv_[i] * block.col(c);
      block.col(c) = y;
    }
  }

  std::vector<Mat6> transfer_;  // -L_{i+1}^T
  std::vector<Mat6> d_inv_;     // D_i^-1
};

}  // namespace evsim
