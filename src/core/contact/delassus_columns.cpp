// The loop's W formed column by column as the status method reads it
// (contact/lcp.h, ColumnOperator). Declared and documented in
// delassus_columns.h.
#include "delassus_columns.h"

#include <algorithm>

namespace evsim::activation {
namespace {

/// Row of the problem -> row of the device, or -1.
std::vector<int> localRows(int rows, const std::vector<int>& of_device) {
  std::vector<int> local(rows, -1);
  for (size_t a = 0; a < of_device.size(); ++a) local[of_device[a]] = static_cast<int>(a);
  return local;
}

}  // namespace

void DelassusColumns::addChain(const ChainInverse* inverse, const std::vector<ContactRow>* rows,
                               const std::vector<int>* of_device) {
  chains_.emplace_back(*inverse, *rows, *of_device);
  chain_local_.push_back(localRows(rows_, *of_device));
}

void DelassusColumns::addDense(MatX W_d, const std::vector<int>* of_device) {
  dense_.push_back({std::move(W_d), of_device, localRows(rows_, *of_device)});
}

void DelassusColumns::rawColumn(int j, double* raw) const {
  std::fill(raw, raw + rows_, 0.0);
  for (size_t k = 0; k < chains_.size(); ++k)
    if (chain_local_[k][j] >= 0) chains_[k].addColumn(chain_local_[k][j], raw);
  for (const Dense& d : dense_) {
    const int b = d.local[j];
    if (b < 0) continue;
    const std::vector<int>& of = *d.of_device;
    for (size_t a = 0; a < of.size(); ++a) raw[of[a]] += d.W(a, b);
  }
}

MatX DelassusColumns::rawColumns(const std::vector<int>& which) const {
  MatX out(rows_, which.size());
  for (size_t k = 0; k < which.size(); ++k) rawColumn(which[k], out.col(k).data());
  return out;
}

void DelassusColumns::eliminate(int m, const MatX* W_HR, const Eigen::LLT<MatX>* S) {
  m_ = m;
  W_HR_ = S ? W_HR : nullptr;
  S_ = S;
}

Eigen::Map<const VecX> DelassusColumns::column(int j) {
  if (storage_.rows() != m_) {
    storage_.resize(m_, m_);
    formed_.assign(m_, 0);
    raw_.resize(rows_);
  }
  if (!formed_[j]) {
    rawColumn(j, raw_.data());
    storage_.col(j) = raw_.head(m_);
    if (S_ && m_ < rows_) storage_.col(j).noalias() -= *W_HR_ * S_->solve(raw_.tail(rows_ - m_));
    formed_[j] = 1;
  }
  return Eigen::Map<const VecX>(storage_.col(j).data(), m_);
}

double DelassusColumns::maxDiagonal() {
  if (m_ == 0) return 0.0;
  VecX diagonal = VecX::Zero(rows_);
  for (const ChainColumns& chain : chains_) chain.addDiagonal(diagonal.data());
  for (const Dense& d : dense_)
    for (size_t a = 0; a < d.of_device->size(); ++a) diagonal((*d.of_device)[a]) += d.W(a, a);
  VecX head = diagonal.head(m_);
  if (S_ && m_ < rows_) {  // minus |L^-1 W_HR(i, :)^T|^2, S = L L^T
    const MatX half = S_->matrixL().solve(W_HR_->transpose());
    head -= half.colwise().squaredNorm().transpose();
  }
  return head.maxCoeff();
}

MatX DelassusColumns::dense() {
  MatX W(m_, m_);
  for (int j = 0; j < m_; ++j) W.col(j) = column(j);
  return W;
}

}  // namespace evsim::activation
