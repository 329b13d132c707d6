#include "endovascular_sim/mechanics/chain_inverse.h"

#include <Eigen/Cholesky>

namespace evsim {

bool ChainInverse::compute(const ChainMatrix& A, int first) {
  const int n = A.numBlocks() - first;
  if (n <= 0) {
    diag_.clear();
    sub_.clear();
    lower_t_.clear();
    return true;
  }
  diag_.resize(n);
  sub_.resize(n - 1);
  lower_t_.resize(n - 1);
  d_inv_.resize(n);
  // Forward: D_i and L_i (stored transposed: L_i^T = D_{i-1}^-1 A_{i-1,i}).
  Mat6 D = A.diag[first];
  for (int i = 0; i < n; ++i) {
    const Eigen::LLT<Mat6> llt(D);
    if (llt.info() != Eigen::Success) return false;
    d_inv_[i] = llt.solve(Mat6::Identity());
    if (i + 1 == n) break;
    const Mat6& upper = A.upper[first + i];  // A_{i,i+1}
    lower_t_[i] = llt.solve(upper);
    D = A.diag[first + i + 1];
    D.noalias() -= upper.transpose() * lower_t_[i];
  }
  // Backward: the band of S.
  diag_[n - 1] = d_inv_[n - 1];
  for (int i = n - 2; i >= 0; --i) {
    sub_[i].noalias() = -diag_[i + 1] * lower_t_[i].transpose();
    diag_[i] = d_inv_[i];
    diag_[i].noalias() += lower_t_[i] * diag_[i + 1] * lower_t_[i].transpose();
    diag_[i] = 0.5 * (diag_[i] + diag_[i].transpose()).eval();
  }
  return true;
}

}  // namespace evsim
