// Sparse Cholesky factorisation of a symmetric positive definite matrix with
// SuiteSparse CHOLMOD. The symbolic analysis (natural ordering, which keeps a
// chain's band) is done once per pattern; the numeric factorisation each step.
#pragma once

#include <vector>

#include "endovascular_sim/core/types.h"

namespace evsim {

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Pattern of the upper triangle in compressed-column form.
  void analyze(int n, const std::vector<int>& col_ptr, const std::vector<int>& row_idx);
  /// Numeric factorisation; false when the matrix is not positive definite.
  bool factorize(const std::vector<double>& values);
  /// Solves A X = B for a block of right-hand sides (n x k).
  void solve(const MatX& B, MatX* X);
  /// Solves A x = b in place.
  void solveInPlace(VecX* x);

  int size() const { return n_; }

 private:
  void solveBuffer(const double* in, int rows, int cols, double* out);
  struct Impl;
  Impl* impl_;
  void* factor_{nullptr};
  int n_{0};
};

}  // namespace evsim
