// Selected inverse of a symmetric positive definite chain matrix (6x6 block
// tridiagonal, mechanics/chain_matrix.h): the blocks of S = A^-1 on the band,
// without the rest of S.
//
// From the block LDL^T of the trailing blocks [first, N)
// (mechanics/chain_factor.h), the band of S from the last block down
// (Takahashi's recursion):
//   S_{n-1,n-1} = D_{n-1}^-1,  S_{i+1,i} = -S_{i+1,i+1} L_{i+1},
//   S_ii = D_i^-1 - L_{i+1}^T S_{i+1,i}.
// Away from the band, column j of S follows from L^T S = D^-1 L^-1 (lower
// triangular): S_ij g = -L_{i+1}^T (S_{i+1,j} g) for i < j, one 6x6
// product per block. The contact solver builds the Delassus operator from
// this (contact/delassus.h). O(N) 6x6 operations; no pivoting (A is SPD).
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/chain_factor.h"
#include "endovascular_sim/mechanics/chain_matrix.h"

namespace evsim {

class ChainInverse {
 public:
  /// Factorises blocks [first, A.numBlocks()) of A and computes the band;
  /// false when a pivot block is not positive definite. `same`, same_blocks:
  /// a shared prefix's factor (ChainFactor::factorize).
  bool compute(const ChainMatrix& A, int first, const ChainFactor* same = nullptr,
               int same_blocks = 0);
  /// The band from a factor already made of the same matrix.
  void computeFrom(const ChainFactor& factor);
  /// Blocks of the factorised part (indices below are relative to `first`).
  int numBlocks() const { return static_cast<int>(diag_.size()); }
  /// S_ii.
  const Mat6& diagonal(int i) const { return diag_[i]; }
  /// S_{i+1,i} (S_{i,i+1} is its transpose).
  const Mat6& subdiagonal(int i) const { return sub_[i]; }
  /// The transfer -L_{i+1}^T: S_ij g = transfer(i) S_{i+1,j} g for i < j
  /// (several columns at once: transfer(i) V).
  const Mat6& transfer(int i) const { return factor_.transfer(i); }
  /// S_ij g for i < j from S_{i+1,j} g.
  Vec6 propagateDown(int i, const Vec6& v_above) const { return transfer(i) * v_above; }
  /// b <- A^-1 b over the factorised blocks (6 numBlocks() entries), from
  /// the block LDL^T.
  void solveInPlace(VecX* b) const { factor_.solveInPlace(b); }
  const ChainFactor& factor() const { return factor_; }

 private:
  void computeBand();
  ChainFactor factor_;
  std::vector<Mat6> diag_;  // S_ii
  std::vector<Mat6> sub_;   // S_{i+1,i}
};

}  // namespace evsim
