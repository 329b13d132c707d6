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
  for (int k = 0; k < 6; ++k) {
    const double pivot = a(k, k);
    if (!(pivot > 0.0)) return false;
    a.row(k) *= 1.0 / pivot;
    for (int i = 0; i < 6; ++i)
      if (i != k) a.row(i) -= a(i, k) * a.row(k);
  }
  if (DinvU) *DinvU = a.middleCols<6>(6);
  const Mat6 inv = a.rightCols<6>();
  *Dinv = 0.5 * (inv + inv.transpose());
  return true;
}

}  // namespace

bool ChainFactor::factorize(const ChainMatrix& A, int first) {
  const int n = std::max(0, A.numBlocks() - first);
  transfer_.resize(std::max(0, n - 1));
  d_inv_.resize(n);
  if (n == 0) return true;
  Mat6 D = A.diag[first], DinvU;
  for (int i = 0; i < n; ++i) {
    if (i + 1 == n) return eliminatePivot(D, nullptr, nullptr, &d_inv_[i]);
    const Mat6& upper = A.upper[first + i];  // A_{i,i+1}
    if (!eliminatePivot(D, &upper, &DinvU, &d_inv_[i])) return false;
    transfer_[i] = -DinvU;
    D = A.diag[first + i + 1];
    D.noalias() -= upper.transpose() * DinvU;
  }
  return true;
}

void ChainFactor::solveInPlace(VecX* b) const {
  const int n = numBlocks();
  // L y = b: y_{i+1} = b_{i+1} - L_{i+1} y_i = b_{i+1} + transfer(i)^T y_i.
  for (int i = 0; i + 1 < n; ++i)
    b->segment<6>(6 * i + 6).noalias() += transfer_[i].transpose() * b->segment<6>(6 * i);
  for (int i = 0; i < n; ++i) b->segment<6>(6 * i) = d_inv_[i] * b->segment<6>(6 * i);
  // L^T x = z: x_i = z_i - L_{i+1}^T x_{i+1} = z_i + transfer(i) x_{i+1}.
  for (int i = n - 2; i >= 0; --i)
    b->segment<6>(6 * i).noalias() += transfer_[i] * b->segment<6>(6 * i + 6);
}

void ChainFactor::solve(const MatX& B, MatX* X) const {
  *X = B;
  const int n = numBlocks();
  for (int i = 0; i + 1 < n; ++i)
    X->middleRows<6>(6 * i + 6).noalias() += transfer_[i].transpose() * X->middleRows<6>(6 * i);
  for (int i = 0; i < n; ++i) X->middleRows<6>(6 * i) = d_inv_[i] * X->middleRows<6>(6 * i);
  for (int i = n - 2; i >= 0; --i)
    X->middleRows<6>(6 * i).noalias() += transfer_[i] * X->middleRows<6>(6 * i + 6);
}

}  // namespace evsim
