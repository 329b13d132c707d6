// Sparse Cholesky factorisation of a symmetric positive definite matrix with
// SuiteSparse CHOLMOD. Declared and documented in
// endovascular_sim/mechanics/sparse_cholesky.h.
#include "endovascular_sim/mechanics/sparse_cholesky.h"

#include <cholmod.h>

#include <cstring>
#include <stdexcept>

namespace evsim {

struct SparseCholesky::Impl {
  cholmod_common common;
  cholmod_sparse* matrix{nullptr};
  cholmod_dense* x{nullptr};  // solve2 workspaces, reused between solves
  cholmod_dense* y{nullptr};
  cholmod_dense* e{nullptr};
};

SparseCholesky::SparseCholesky() : impl_(new Impl) {
  cholmod_start(&impl_->common);
  impl_->common.nmethods = 1;
  impl_->common.method[0].ordering = CHOLMOD_NATURAL;
  impl_->common.postorder = false;
  impl_->common.print = 0;
  impl_->common.final_ll = true;  // LL^T: a non-positive pivot is reported
}

SparseCholesky::~SparseCholesky() {
  cholmod_common* c = &impl_->common;
  if (factor_) {
    auto* f = static_cast<cholmod_factor*>(factor_);
    cholmod_free_factor(&f, c);
  }
  cholmod_free_sparse(&impl_->matrix, c);
  cholmod_free_dense(&impl_->x, c);
  cholmod_free_dense(&impl_->y, c);
  cholmod_free_dense(&impl_->e, c);
  cholmod_finish(c);
  delete impl_;
}

void SparseCholesky::analyze(int n, const std::vector<int>& col_ptr,
                             const std::vector<int>& row_idx) {
  cholmod_common* c = &impl_->common;
  if (factor_) {
    auto* f = static_cast<cholmod_factor*>(factor_);
    cholmod_free_factor(&f, c);
    factor_ = nullptr;
  }
  cholmod_free_sparse(&impl_->matrix, c);
  n_ = n;
  if (n == 0) return;
  const size_t nnz = row_idx.size();
  impl_->matrix =
      cholmod_allocate_sparse(n, n, nnz, /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, c);
  std::memcpy(impl_->matrix->p, col_ptr.data(), sizeof(int) * (n + 1));
  std::memcpy(impl_->matrix->i, row_idx.data(), sizeof(int) * nnz);
  std::memset(impl_->matrix->x, 0, sizeof(double) * nnz);
  factor_ = cholmod_analyze(impl_->matrix, c);
  if (!factor_) throw std::runtime_error("CHOLMOD analysis failed");
}

bool SparseCholesky::factorize(const std::vector<double>& values) {
  if (n_ == 0) return true;
  std::memcpy(impl_->matrix->x, values.data(), sizeof(double) * values.size());
  auto* f = static_cast<cholmod_factor*>(factor_);
  cholmod_factorize(impl_->matrix, f, &impl_->common);
  return impl_->common.status == CHOLMOD_OK && f->minor == f->n;
}

void SparseCholesky::solveBuffer(const double* in, int rows, int cols, double* out) {
  if (n_ == 0 || cols == 0) return;
  cholmod_dense b;
  b.nrow = rows;
  b.ncol = cols;
  b.nzmax = static_cast<size_t>(rows) * cols;
  b.d = rows;
  b.x = const_cast<double*>(in);
  b.z = nullptr;
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_solve2(CHOLMOD_A, static_cast<cholmod_factor*>(factor_), &b, nullptr, &impl_->x, nullptr,
                 &impl_->y, &impl_->e, &impl_->common);
  std::memcpy(out, impl_->x->x, sizeof(double) * b.nzmax);
}

void SparseCholesky::solve(const MatX& B, MatX* X) {
  X->resize(B.rows(), B.cols());
  solveBuffer(B.data(), static_cast<int>(B.rows()), static_cast<int>(B.cols()), X->data());
}

void SparseCholesky::solveInPlace(VecX* x) {
  solveBuffer(x->data(), static_cast<int>(x->size()), 1, x->data());
}

}  // namespace evsim
