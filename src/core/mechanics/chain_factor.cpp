// Block LDL^T of a chain matrix (mechanics/chain_factor.h): the free
// motion's factor of A, and of A + C in the contact solver.
#include "endovascular_sim/mechanics/chain_factor.h"

#include <Eigen/Cholesky>

namespace evsim {

bool ChainFactor::factorize(const ChainMatrix& A, int first) {
  const int n = std::max(0, A.numBlocks() - first);
  transfer_.resize(std::max(0, n - 1));
  d_inv_.resize(n);
  if (n == 0) return true;
  Mat6 D = A.diag[first];
  for (int i = 0; i < n; ++i) {
    const Eigen::LLT<Mat6> llt(D);
    if (llt.info() != Eigen::Success) return false;
    d_inv_[i] = llt.solve(Mat6::Identity());
    if (i + 1 == n) break;
    const Mat6& upper = A.upper[first + i];  // A_{i,i+1}
    transfer_[i] = -llt.solve(upper);
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
