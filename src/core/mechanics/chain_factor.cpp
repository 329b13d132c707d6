// Block LDL^T of a chain matrix (mechanics/chain_factor.h): the free
// motion's factor of A, and of A + C in the contact solver.
#include "endovascular_sim/mechanics/chain_factor.h"

#include <algorithm>

namespace evsim {

namespace {

/// [D | U | I] of one pivot, row-major so that a row operation is one
/// vectorised pass over 18 contiguous numbers.
using Augmented = Eigen::Matrix<double, 6, 18, Eigen::RowMajor>;

/// D^-1 U and D^-1 of a symmetric positive definite 6x6 pivot D, by
/// Gauss-Jordan elimination of [D | U | I]: U is eliminated with D itself,
/// never multiplied by a formed D^-1 (with D^-1 formed first, a stiff wire,
/// cond(A) ~ 1e13, lost a digit and a half of W). No pivoting: the pivots of
/// an SPD matrix are its Schur complements' diagonals, positive. False when
/// one is not (D is not positive definite).
bool eliminatePivot(const Mat6& D, const Mat6* U, Mat6* DinvU, Mat6* Dinv) {
  Augmented a;
  a.leftCols<6>() = D;
  if (U)
    a.middleCols<6>(6) = *U;
  else
    a.middleCols<6>(6).setZero();
  a.rightCols<6>().setIdentity();
  // At pivot k only columns k+1 .. k+12 change: D's columns up to k are
  // eliminated (their entries in row k are 0), I's beyond 12 + k untouched
  // (0 in row k). The window skips only operations on exact zeros (the same
  // numbers as over the whole row) and is 12 wide: three vector operations
  // in place of five (120 ns a pivot in place of 155).
  for (int k = 0; k < 6; ++k) {
    const double pivot = a(k, k);
    if (!(pivot > 0.0)) return false;
    auto pivot_row = a.row(k).segment<12>(k + 1);
    pivot_row *= 1.0 / pivot;
    for (int i = 0; i < 6; ++i) {
      if (i == k) continue;
      const double f = a(i, k);
      a.row(i).segment<12>(k + 1) -= f * pivot_row;
    }
  }
  if (DinvU) *DinvU = a.middleCols<6>(6);
  const Mat6 inv = a.rightCols<6>();
  *Dinv = 0.5 * (inv + inv.transpose());
  return true;
}

}  // namespace

bool ChainFactor::factorize(const ChainMatrix& A, int first, const ChainFactor* same,
                            int same_blocks) {
  const int n = std::max(0, A.numBlocks() - first);
  transfer_.resize(std::max(0, n - 1));
  d_inv_.resize(n);
  if (n == 0) return true;
  // The pivots before block k depend on A's blocks before k only: a prefix
  // the two matrices share is copied (the same numbers as eliminated).
  const int k = same ? std::clamp(same_blocks, 0, std::min(n - 1, same->numBlocks() - 1)) : 0;
  Mat6 D, DinvU;
  if (k > 0) {
    std::copy(same->transfer_.begin(), same->transfer_.begin() + k, transfer_.begin());
    std::copy(same->d_inv_.begin(), same->d_inv_.begin() + k, d_inv_.begin());
    DinvU = -transfer_[k - 1];
    D = A.diag[first + k];
    D.noalias() -= A.upper[first + k - 1].transpose() * DinvU;
  } else {
    D = A.diag[first];
  }
  for (int i = k; i < n; ++i) {
    if (i + 1 == n) return eliminatePivot(D, nullptr, nullptr, &d_inv_[i]);
    const Mat6& upper = A.upper[first + i];  // A_{i,i+1}
    if (!eliminatePivot(D, &upper, &DinvU, &d_inv_[i])) return false;
    transfer_[i] = -DinvU;
    D = A.diag[first + i + 1];
    D.noalias() -= upper.transpose() * DinvU;
  }
  return true;
}

void ChainFactor::solveInPlace(VecX* b, int first_nonzero) const {
  const int n = numBlocks();
  // L y = b: y_{i+1} = b_{i+1} - L_{i+1} y_i = b_{i+1} + transfer(i)^T y_i
  // (zero before the first nonzero block, as D^-1 y there).
  for (int i = std::max(first_nonzero, 0); i + 1 < n; ++i)
    b->segment<6>(6 * i + 6).noalias() += transfer_[i].transpose() * b->segment<6>(6 * i);
  for (int i = std::max(first_nonzero, 0); i < n; ++i)
    b->segment<6>(6 * i) = d_inv_[i] * b->segment<6>(6 * i);
  // L^T x = z: x_i = z_i - L_{i+1}^T x_{i+1} = z_i + transfer(i) x_{i+1}.
  for (int i = n - 2; i >= 0; --i)
    b->segment<6>(6 * i).noalias() += transfer_[i] * b->segment<6>(6 * i + 6);
}

void ChainFactor::solve(const MatX& B, MatX* X) const {
  *X = B;
  solveInPlace(X);
}

void ChainFactor::solveInPlace(MatX* X, int first_nonzero) const {
  const int n = numBlocks();
  // Below the first nonzero block the forward pass and D^-1 carry zeros:
  // skipped, the same numbers.
  // Products of a 6 x 6 block with a 6-row block of X are lazy (column by
  // column, no temporary on the heap), D^-1 applied column by column.
  for (int i = std::max(first_nonzero, 0); i + 1 < n; ++i)
    X->middleRows<6>(6 * i + 6) += transfer_[i].transpose().lazyProduct(X->middleRows<6>(6 * i));
  for (int i = std::max(first_nonzero, 0); i < n; ++i)
    applyPivotInverse(i, X->middleRows<6>(6 * i));
  for (int i = n - 2; i >= 0; --i)
    X->middleRows<6>(6 * i) += transfer_[i].lazyProduct(X->middleRows<6>(6 * i + 6));
}

void ChainFactor::solveTrailingInPlace(MatX* X, int first) const {
  const int n = numBlocks();
  auto block = [&](int i) { return X->middleRows<6>(6 * (i - first)); };
  for (int i = first; i + 1 < n; ++i)
    block(i + 1) += transfer_[i].transpose().lazyProduct(block(i));
  for (int i = first; i < n; ++i) applyPivotInverse(i, block(i));
  for (int i = n - 2; i >= first; --i) block(i) += transfer_[i].lazyProduct(block(i + 1));
}

}  // namespace evsim
