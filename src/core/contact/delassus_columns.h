// The loop's W formed column by column as the status method reads it
// (contact/lcp.h, ColumnOperator). Internal to the contact layer.
//
// A step of a wire in a catheter has 200-300 contact rows (a lumen row per
// point of the wire inside, a wall row per point near the wall) of which
// 20-50 carry a force; the status method reads the columns of those only.
// Formed whole, W cost two thirds of such a step: every row is linearised
// anew at each loop's x, so nothing of the last loop's W could be kept,
// and the lumen springs' elimination W_HH - W_HR S^-1 W_RH was a dense
// product of m x m x r. Here a column costs one pass along each chain it
// touches (contact/delassus.h, ChainColumns), and the elimination
// one product of m x r per column read.
#pragma once

#include <Eigen/Cholesky>
#include <vector>

#include "endovascular_sim/contact/delassus.h"
#include "endovascular_sim/contact/lcp.h"

namespace evsim::activation {

class DelassusColumns final : public ColumnOperator {
 public:
  /// rows: the rows of the problem (contacts' and springs', before the
  /// springs' elimination).
  explicit DelassusColumns(int rows) : rows_(rows), m_(rows) {}

  /// A device whose part of W comes from the band of A^-1 (kept alive by
  /// the caller): its rows of H and their rows in the problem.
  void addChain(const ChainInverse* inverse, const std::vector<ContactRow>* rows,
                const std::vector<int>* of_device);
  /// A device whose part of W was formed whole (few rows): W_d, and its
  /// rows in the problem.
  void addDense(MatX W_d, const std::vector<int>* of_device);

  /// Columns `which` of W before the elimination (rows x which.size()).
  MatX rawColumns(const std::vector<int>& which) const;

  /// The rows from m on are springs, eliminated: W <- W_HH - W_HR S^-1 W_RH
  /// with W_HR (m x r) and the factor of S (lumen_curvature.cpp; both kept
  /// alive by the caller); without S (not positive definite), W_HH alone.
  void eliminate(int m, const MatX* W_HR, const Eigen::LLT<MatX>* S);

  int size() const override { return m_; }
  Eigen::Map<const VecX> column(int j) override;
  double maxDiagonal() override;
  /// Every column (an LCP record: --dump-lcp, tests).
  MatX dense();

 private:
  struct Dense {
    MatX W;
    const std::vector<int>* of_device;
    std::vector<int> local;  // row of the problem -> row of W, or -1
  };
  /// Column j before the elimination into raw (rows entries).
  void rawColumn(int j, double* raw) const;

  int rows_;  // before the elimination
  int m_;     // after it
  std::vector<ChainColumns> chains_;
  std::vector<std::vector<int>> chain_local_;  // per chain: row of the problem -> its row, or -1
  std::vector<Dense> dense_;
  const MatX* W_HR_{nullptr};
  const Eigen::LLT<MatX>* S_{nullptr};
  MatX storage_;              // m x m, the columns formed so far
  std::vector<char> formed_;  // per column
  VecX raw_;                  // a column before the elimination
};

}  // namespace evsim::activation
