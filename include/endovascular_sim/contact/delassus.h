// The Delassus operator W = H A^-1 H^T of one device, without forming A^-1.
//
// Each contact row of H has 12 non-zeros (two nodes). Two ways, both O(c n)
// for a chain of n nodes:
//  - chainDelassusOperator (the contact solver's): from the band of A^-1
//    (mechanics/chain_inverse.h), each row's column A^-1 h_j is started at
//    its element and carried down the chain (settled columns through one
//    6x6 transfer per node, recent ones explicitly) and dotted with every
//    row whose element lies below: W_ij for i <= j, no triangular solve, no
//    n x c matrix; updateChainDelassusOperator updates a previous W in
//    place for the rows that changed since (with few, their columns alone:
//    carried down and their rows up the chain) and keeps the rest;
//  - delassusOperator: one block solve with c right-hand sides
//    gives Y = A^-1 H^T (banded triangular solves, both directions over the
//    whole chain, or with TrailingSolve only from the first node a row
//    reaches), then W_ij = h_i . Y_j over the 12 non-zeros of h_i.
// The naive alternative, c separate solves and a dense product H Y
// (O(c n) + O(c^2 n)), is measured against both in the benchmarks.
#pragma once

#include <vector>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/mechanics/chain_inverse.h"

namespace evsim {

/// A row of H restricted to one device: one or two parts (a self contact
/// touches two elements of the device), each the offset of its first node
/// among the free DOFs (6 * (node - first_free), negative for a held node)
/// and its 12 coefficients.
struct ContactRow {
  int parts{1};
  int offset[2]{0, 0};
  Row12 h[2]{Row12::Zero(), Row12::Zero()};
};

/// H^T (free DOFs x c) of the rows over n free DOFs.
MatX transposedRows(int n, const std::vector<ContactRow>& rows);
/// W = H Y (c x c) from Y = A^-1 H^T, whose first row is free DOF
/// `first_dof` (the rows reach none before it).
void rowsTimes(const std::vector<ContactRow>& rows, const MatX& Y, MatX* W, int first_dof = 0);

/// A^-1 H^T from the first free node a row reaches on: above it (towards
/// the proximal end) A^-1 H^T is carried up the chain from there
/// (through ChainFactor::transfer), not solved for every row.
struct TrailingSolve {
  MatX Y;  // blocks [first_block, n) of A^-1 H^T (6 (n - first_block) x c)
  int first_block{0};
};

/// Y's trailing blocks and W = H Y, with the device's chain factor: the
/// same W as delassusOperator's, the triangular solves only below the
/// rows' first node.
void delassusOperator(const ChainFactor& factor, const std::vector<ContactRow>& rows,
                      TrailingSolve* Y, MatX* W);

/// *dq (the factor's size() entries) += A^-1 H^T l from Y's trailing blocks.
void addSolveTimes(const ChainFactor& factor, const TrailingSolve& Y, const VecX& l,
                   Eigen::Ref<VecX> dq);

/// Y = A^-1 H^T (free DOFs x c) and W = H Y (c x c), with any factor of A
/// over the free nodes that solves a block of right-hand sides: the
/// device's chain factor (mechanics/chain_factor.h) in the contact solver,
/// CHOLMOD's (mechanics/sparse_cholesky.h) as an independent check.
template <typename Factor>
void delassusOperator(Factor& factor, const std::vector<ContactRow>& rows, MatX* Y, MatX* W) {
  factor.solve(transposedRows(factor.size(), rows), Y);
  rowsTimes(rows, *Y, W);
}
/// The chain factor's: H^T formed in Y and solved in place, its forward
/// pass from the first block a row reaches (the same numbers, without the
/// copy of H^T and the zeros below the rows).
void delassusOperator(const ChainFactor& factor, const std::vector<ContactRow>& rows, MatX* Y,
                      MatX* W);

/// W = H A^-1 H^T (c x c) from the selected inverse of A over the free
/// nodes.
void chainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                           MatX* W);

/// One device's W kept across the loops of a step: the c x c operator is
/// the top-left corner of `storage`, whose capacity grows by half when the
/// rows outgrow it, so the rows a loop adds cost no copy of the kept
/// entries (a copy of c^2 entries per loop, with its page faults, was 3-4 %
/// of the packed coil's step).
struct DelassusBuffer {
  MatX storage;  // capacity x capacity
  int size{0};   // c
  Eigen::Block<MatX> matrix() { return storage.topLeftCorner(size, size); }
  MatXView view() const { return storage.topLeftCorner(size, size); }
};

/// How the update reaches the fresh rows' entries: chosen by their share
/// (automatic), or forced (benchmarks, tests): their columns alone, carried
/// down and their rows up the chain, or one sweep carrying every column.
enum class DelassusUpdate { kAutomatic, kFreshColumns, kSweep };

/// The same W after some rows changed, the inverse unchanged, in place: on
/// entry W holds the operator of its first W->size rows (at most
/// rows.size()); of those, the rows with fresh_rows[i] != 0 changed (rows
/// beyond are new). Entries between two unchanged rows are kept; only the
/// others are computed (O(n k + c k) for k fresh rows, against
/// O(n + c^2)).
void updateChainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                                 const std::vector<char>& fresh_rows, DelassusBuffer* W,
                                 DelassusUpdate path = DelassusUpdate::kAutomatic);

/// The same on an exactly sized W (W->rows() kept rows on entry, c on
/// return).
void updateChainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                                 const std::vector<char>& fresh_rows, MatX* W,
                                 DelassusUpdate path = DelassusUpdate::kAutomatic);

/// One part of a row of H on the nodes (node, node + 1) of the free chain.
struct ChainPart {
  int row;
  int node;
  Vec6 lo, hi;  // coefficients on the two nodes
};

/// Columns of W = H A^-1 H^T one at a time from the selected inverse (the
/// status method's columns on demand: contact/delassus_columns.h): the
/// rows sorted along the chain and each row's own column at its node
/// once; then a column is carried down and its row up the chain from its
/// element, O(n + c) per column.
class ChainColumns {
 public:
  /// `to`: each row's index in the caller's vectors. The inverse must
  /// outlive this.
  ChainColumns(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
               std::vector<int> to);
  /// out[to[i]] += W_ij for every row i.
  void addColumn(int j, double* out) const;
  /// out[to[i]] += W_ii for every row i.
  void addDiagonal(double* out) const;

 private:
  template <typename Sink>
  void forColumn(int j, Sink&& sink) const;

  const ChainInverse* inverse_;
  std::vector<ChainPart> parts_;  // sorted by node
  std::vector<Vec6> here_;        // per part: its own column S g at its node
  std::vector<int> to_;
  std::vector<std::vector<int>> parts_of_row_;
};

/// H^T lambda over the free DOFs (n): the generalised force of the rows.
VecX contactForce(int n, const std::vector<ContactRow>& rows, const VecX& lambda);

}  // namespace evsim
