// Symmetric block-tridiagonal matrix with 6x6 blocks: the system matrix of a
// chain of 6-DOF nodes. Block (i, i) is diag[i]; block (i, i+1) is upper[i].
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"

namespace evsim {

struct ChainMatrix {
  std::vector<Mat6> diag;   // (num_blocks)
  std::vector<Mat6> upper;  // (num_blocks - 1)

  void resize(int num_blocks);
  void setZero();
  int numBlocks() const { return static_cast<int>(diag.size()); }
  /// y = A x for x of size 6 * numBlocks().
  VecX multiply(const VecX& x) const;
  /// Dense copy (tests).
  MatX toDense() const;
};

/// Upper-triangle CSC pattern of the trailing blocks [first, numBlocks) of a
/// chain matrix, in natural (chain) order: the band is kept, no fill-in.
struct ChainCscPattern {
  int first_block{0};
  int size{0};  // matrix dimension
  std::vector<int> col_ptr;
  std::vector<int> row_idx;
  void build(int num_blocks, int first);
  /// Values of blocks [first_block, ...) of A in this pattern's order.
  void gather(const ChainMatrix& A, std::vector<double>* values) const;
};

}  // namespace evsim
