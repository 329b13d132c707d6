// The band of A^-1 from the block LDL^T of a chain matrix
// (mechanics/chain_inverse.h): what the Delassus operator's sweep needs.
#include "endovascular_sim/mechanics/chain_inverse.h"

namespace evsim {

bool ChainInverse::compute(const ChainMatrix& A, int first, const ChainFactor* same,
                           int same_blocks) {
  if (!factor_.factorize(A, first, same, same_blocks)) return false;
  computeBand();
  return true;
}

void ChainInverse::computeFrom(const ChainFactor& factor) {
  factor_ = factor;
  computeBand();
}

void ChainInverse::computeBand() {
  const int n = factor_.numBlocks();
  diag_.resize(n);
  sub_.resize(std::max(0, n - 1));
  if (n == 0) return;
  diag_[n - 1] = factor_.pivotInverse(n - 1);
  for (int i = n - 2; i >= 0; --i) {
    sub_[i].noalias() = diag_[i + 1] * factor_.transfer(i).transpose();
    diag_[i] = factor_.pivotInverse(i);
    diag_[i].noalias() += factor_.transfer(i) * sub_[i];  // T S_{i+1,i+1} T^T
    diag_[i] = 0.5 * (diag_[i] + diag_[i].transpose()).eval();
  }
}

}  // namespace evsim
