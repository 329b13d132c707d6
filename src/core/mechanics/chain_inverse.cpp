#include "endovascular_sim/mechanics/chain_inverse.h"

#include <Eigen/Cholesky>

namespace evsim {

bool ChainInverse::compute(const ChainMatrix& A, int first) {
  const int n = A.numBlocks() - first;
  if (n <= 0) {
    diag_.clear();
    sub_.clear();
    transfer_.clear();
    return true;
  }
  diag_.resize(n);
  sub_.resize(n - 1);
  transfer_.resize(n - 1);
  d_inv_.resize(n);
  // Forward: D_i and L_i, stored as the transfer -L_{i+1}^T =
  // -D_i^-1 A_{i,i+1}.
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
  // Backward: the band of S.
  diag_[n - 1] = d_inv_[n - 1];
  for (int i = n - 2; i >= 0; --i) {
    sub_[i].noalias() = diag_[i + 1] * transfer_[i].transpose();
    diag_[i] = d_inv_[i];
    diag_[i].noalias() += transfer_[i] * sub_[i];  // T S_{i+1,i+1} T^T
    diag_[i] = 0.5 * (diag_[i] + diag_[i].transpose()).eval();
  }
  return true;
}

void ChainInverse::solveInPlace(VecX* b) const {
  const int n = numBlocks();
  // L y = b: y_{i+1} = b_{i+1} - L_{i+1} y_i = b_{i+1} + transfer(i)^T y_i.
  for (int i = 0; i + 1 < n; ++i)
    b->segment<6>(6 * i + 6).noalias() += transfer_[i].transpose() * b->segment<6>(6 * i);
  for (int i = 0; i < n; ++i) b->segment<6>(6 * i) = d_inv_[i] * b->segment<6>(6 * i);
  // L^T x = z: x_i = z_i - L_{i+1}^T x_{i+1} = z_i + transfer(i) x_{i+1}.
  for (int i = n - 2; i >= 0; --i)
    b->segment<6>(6 * i).noalias() += transfer_[i] * b->segment<6>(6 * i + 6);
}

}  // namespace evsim
