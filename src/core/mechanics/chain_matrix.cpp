// Symmetric block-tridiagonal matrix with 6x6 blocks: the system matrix of a
// chain of 6-DOF nodes. Declared and documented in
// endovascular_sim/mechanics/chain_matrix.h.
#include "endovascular_sim/mechanics/chain_matrix.h"

namespace evsim {

void ChainMatrix::resize(int num_blocks) {
  diag.resize(num_blocks);
  upper.resize(num_blocks > 0 ? num_blocks - 1 : 0);
}

void ChainMatrix::setZero() {
  for (auto& b : diag) b.setZero();
  for (auto& b : upper) b.setZero();
}

VecX ChainMatrix::multiply(const VecX& x) const {
  const int n = numBlocks();
  VecX y = VecX::Zero(6 * n);
  for (int i = 0; i < n; ++i) y.segment<6>(6 * i) += diag[i] * x.segment<6>(6 * i);
  for (int i = 0; i + 1 < n; ++i) {
    y.segment<6>(6 * i) += upper[i] * x.segment<6>(6 * i + 6);
    y.segment<6>(6 * i + 6) += upper[i].transpose() * x.segment<6>(6 * i);
  }
  return y;
}

MatX ChainMatrix::toDense() const {
  const int n = numBlocks();
  MatX a = MatX::Zero(6 * n, 6 * n);
  for (int i = 0; i < n; ++i) a.block<6, 6>(6 * i, 6 * i) = diag[i];
  for (int i = 0; i + 1 < n; ++i) {
    a.block<6, 6>(6 * i, 6 * i + 6) = upper[i];
    a.block<6, 6>(6 * i + 6, 6 * i) = upper[i].transpose();
  }
  return a;
}

void ChainCscPattern::build(int num_blocks, int first) {
  first_block = first;
  const int nb = num_blocks - first;
  size = 6 * nb;
  col_ptr.assign(size + 1, 0);
  row_idx.clear();
  for (int b = 0; b < nb; ++b) {
    for (int c = 0; c < 6; ++c) {
      const int col = 6 * b + c;
      if (b > 0)
        for (int r = 0; r < 6; ++r) row_idx.push_back(6 * (b - 1) + r);
      for (int r = 0; r <= c; ++r) row_idx.push_back(6 * b + r);
      col_ptr[col + 1] = static_cast<int>(row_idx.size());
    }
  }
}

void ChainCscPattern::gather(const ChainMatrix& A, std::vector<double>* values) const {
  values->resize(row_idx.size());
  double* v = values->data();
  const int nb = size / 6;
  for (int b = 0; b < nb; ++b) {
    const int blk = first_block + b;
    for (int c = 0; c < 6; ++c) {
      if (b > 0)
        for (int r = 0; r < 6; ++r) *v++ = A.upper[blk - 1](r, c);
      for (int r = 0; r <= c; ++r) *v++ = A.diag[blk](r, c);
    }
  }
}

}  // namespace evsim
