// Block LDL^T of a chain matrix (mechanics/chain_factor.h): the free
// motion's factor of A, and of A + C in the contact solver.
#include "endovascular_sim/mechanics/chain_factor.h"

#include <algorithm>
#include <cmath>

namespace evsim {

namespace {

/// The inverse M = L^-1 of the Cholesky factor of a symmetric positive
/// definite 6x6 block (A = L L^T, A^-1 = M^T M), written out for the fixed
/// size: Eigen's LLT takes its general-size triangular solves for 6x6, three
/// times as slow. False when A is not positive definite.
bool inverseCholeskyFactor(const Mat6& A, Mat6* M) {
  double L[6][6] = {};
  for (int j = 0; j < 6; ++j) {
    double d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0.0)) return false;
    L[j][j] = std::sqrt(d);
    for (int i = j + 1; i < 6; ++i) {
      double s = A(i, j);
      for (int k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      L[i][j] = s / L[j][j];
    }
  }
  M->setZero();
  for (int j = 0; j < 6; ++j) {
    (*M)(j, j) = 1.0 / L[j][j];
    for (int i = j + 1; i < 6; ++i) {
      double s = 0.0;
      for (int k = j; k < i; ++k) s -= L[i][k] * (*M)(k, j);
      (*M)(i, j) = s / L[i][i];
    }
  }
  return true;
}

}  // namespace

bool ChainFactor::factorize(const ChainMatrix& A, int first) {
  const int n = std::max(0, A.numBlocks() - first);
  transfer_.resize(std::max(0, n - 1));
  d_inv_.resize(n);
  if (n == 0) return true;
  Mat6 D = A.diag[first], M, MU;
  for (int i = 0; i < n; ++i) {
    if (!inverseCholeskyFactor(D, &M)) return false;
    d_inv_[i].noalias() = M.transpose() * M;
    if (i + 1 == n) break;
    const Mat6& upper = A.upper[first + i];  // A_{i,i+1}
    // -D^-1 A_{i,i+1} through the two triangular factors: with D^-1 formed
    // first, a stiff wire (cond(A) ~ 1e13) lost a digit and a half of W.
    MU.noalias() = M * upper;
    transfer_[i].noalias() = -M.transpose() * MU;
    D = A.diag[first + i + 1];
    D.noalias() += upper.transpose() * transfer_[i];
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
