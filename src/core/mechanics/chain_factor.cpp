// Block LDL^T of a chain matrix (mechanics/chain_factor.h): the free
// motion's factor of A, and of A + C in the contact solver.
#include "endovascular_sim/mechanics/chain_factor.h"

#include <algorithm>
#include <cmath>

namespace evsim {

namespace {

/// The inverse of a symmetric positive definite 6x6 block by its Cholesky
/// factor L (A = L L^T, inverse = L^-T L^-1), written out for the fixed
/// size: twice as fast as Eigen's LLT solve with the identity, whose
/// triangular solves take the general-size path. False when A is not
/// positive definite.
bool spdInverse(const Mat6& A, Mat6* inverse) {
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
  double M[6][6] = {};  // L^-1, lower triangular
  for (int j = 0; j < 6; ++j) {
    M[j][j] = 1.0 / L[j][j];
    for (int i = j + 1; i < 6; ++i) {
      double s = 0.0;
      for (int k = j; k < i; ++k) s -= L[i][k] * M[k][j];
      M[i][j] = s / L[i][i];
    }
  }
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j <= i; ++j) {
      double s = 0.0;
      for (int k = i; k < 6; ++k) s += M[k][i] * M[k][j];
      (*inverse)(i, j) = (*inverse)(j, i) = s;
    }
  return true;
}

}  // namespace

bool ChainFactor::factorize(const ChainMatrix& A, int first) {
  const int n = std::max(0, A.numBlocks() - first);
  transfer_.resize(std::max(0, n - 1));
  d_inv_.resize(n);
  if (n == 0) return true;
  Mat6 D = A.diag[first];
  for (int i = 0; i < n; ++i) {
    if (!spdInverse(D, &d_inv_[i])) return false;
    if (i + 1 == n) break;
    const Mat6& upper = A.upper[first + i];  // A_{i,i+1}
    transfer_[i].noalias() = -d_inv_[i] * upper;
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
