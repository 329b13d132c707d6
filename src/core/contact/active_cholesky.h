// The status method's factor of its active set (lcp.cpp): a Cholesky factor
// updated a row at a time, kept in the caller's LcpWorkspace from one solve
// to the next. Internal to the contact solver.
#pragma once

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "endovascular_sim/contact/lcp.h"
#include "endovascular_sim/core/types.h"

namespace evsim {

/// The factor buffer of an LcpWorkspace (contact/lcp.h), at least c x c
/// (grown by a quarter at least when smaller, the factor kept in it copied
/// along: the next loop has more rows; entries are written before they are
/// read), and what the last solve left in it (keep).
struct LcpWorkspace::FactorStore {
  MatX L;
  bool valid{false};     // L's top-left block factorises entries + eps I
  std::vector<int> set;  // the rows and columns of W it factorises, in order
  double eps{0.0};
  MatX entries;  // W(set[i], set[j]), i >= j, where they were factorised
};

/// Cholesky factor L (lower) of W_aa + eps I for an ordered active set,
/// updated by appending or removing one index, and the forward solution
/// y = L^-1 b_a of a right-hand side b (given at construction) kept with
/// it: O(k) per change, so each pivot's z_a = L^-T y is one triangular
/// solve. All storage is sized once (c x c), so pivots allocate nothing;
/// L lives in the workspace's buffer that only grows, so that the solves of
/// an activation loop (megabytes at c = 400) do not each allocate and
/// fault in their own, and the next solve may start from the factor the
/// last one kept there (keep, resume). One factor at a time per workspace.
template <typename Columns>
class ActiveCholesky {
 public:
  ActiveCholesky(const Columns& W, const VecX& b, double eps, LcpWorkspace* workspace)
      : W_(W),
        b_(b),
        eps_(eps),
        store_(factorStore(workspace, W.size())),
        L_(store_.L.topLeftCorner(W.size(), W.size())),
        row_(W.size()),
        y_(W.size()) {
    set_.reserve(W.size());
  }

  int size() const { return static_cast<int>(set_.size()); }
  /// Whether reset started from the factor the last solve kept.
  bool resumed() const { return resumed_; }
  const std::vector<int>& set() const { return set_; }

  /// Starts from the ordered set `init`: from the factor the last solve
  /// kept, where `may_resume` and most of it stands (resume; then ordered
  /// as there), else
  /// with one blocked factorisation in place; if it is not positive
  /// definite, index by index, leaving out those whose pivot is not
  /// positive (dependent rows).
  void reset(const std::vector<int>& init, bool may_resume = true) {
    set_.clear();
    const bool kept = store_.valid;
    store_.valid = false;  // (L changes from here on)
    if (kept && may_resume && resume(init)) return;
    const int k = static_cast<int>(init.size());
    if (k == 0) return;
    for (int j = 0; j < k; ++j) {
      const auto column = W_.col(init[j]);
      for (int i = j; i < k; ++i) L_(i, j) = column(init[i]);
    }
    L_.diagonal().head(k).array() += eps_;
    Eigen::Ref<MatX> block = L_.topLeftCorner(k, k);
    const Eigen::LLT<Eigen::Ref<MatX>> llt(block);
    if (llt.info() == Eigen::Success) {
      set_ = init;
      for (int j = 0; j < k; ++j) y_(j) = b_(init[j]);
      L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(y_.head(k));
      return;
    }
    for (int i : init) add(i);
  }

  /// Leaves this factor in the thread's store for the next solve's reset
  /// (resume), with the entries of W it factorises.
  void keep() {
    if constexpr (!Columns::kWholeColumns) return;  // (its columns formed on demand)
    const int k = size();
    store_.set = set_;
    store_.eps = eps_;
    store_.entries.resize(k, k);
    for (int j = 0; j < k; ++j) {
      const auto column = W_.col(set_[j]);
      for (int i = j; i < k; ++i) store_.entries(i, j) = column(set_[i]);
    }
    store_.valid = true;
  }

  /// Appends index i; false when the pivot is not positive (then unchanged).
  bool add(int i) {
    const int k = size();
    auto row = row_.head(k);
    const auto column = W_.col(i);  // (W symmetric: its row i)
    for (int j = 0; j < k; ++j) row(j) = column(set_[j]);
    if (k) L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(row);
    const double d2 = column(i) + eps_ - row.squaredNorm();
    if (!(d2 > 0.0)) return false;
    L_.row(k).head(k) = row.transpose();
    L_(k, k) = std::sqrt(d2);
    y_(k) = (b_(i) - row.dot(y_.head(k))) / L_(k, k);
    set_.push_back(i);
    return true;
  }

  /// Removes the entry at position p; Givens rotations restore L (and,
  /// applied to y, keep L y = b_a).
  void removeAt(int p) {
    const int k = size();
    // Rows p + 1 .. k - 1 move up one, column by column (contiguous in the
    // column-major L; row by row each entry was a cache line of its own).
    for (int j = 0; j < k; ++j) {
      double* col = L_.col(j).data();
      std::copy(col + p + 1, col + k, col + p);
    }
    // Rows p..k-2 now have a super-diagonal entry in column c+1: rotate
    // columns (c, c+1) to zero it.
    for (int c = p; c + 1 < k; ++c) {
      const double a = L_(c, c), b = L_(c, c + 1);
      // (L's entries lie near sqrt(diag W): a^2 + b^2 neither overflows nor
      // underflows, and std::hypot's care for that, taken every time, cost
      // 1.5 % of a packed coil's step; it is kept for the extremes)
      double r = std::sqrt(a * a + b * b);
      if (!(r > 1e-150 && r < 1e150)) r = std::hypot(a, b);
      const double cs = a / r, sn = b / r;
      for (int rr = c; rr + 1 < k; ++rr) {
        const double x = L_(rr, c), y = L_(rr, c + 1);
        L_(rr, c) = cs * x + sn * y;
        L_(rr, c + 1) = -sn * x + cs * y;
      }
      const double yc = y_(c), yn = y_(c + 1);
      y_(c) = cs * yc + sn * yn;
      y_(c + 1) = -sn * yc + cs * yn;
    }
    set_.erase(set_.begin() + p);
  }

  /// z_a with (W_aa + eps I) z_a = b_a (ordered like set()).
  template <typename Vector>
  void solution(Vector&& za) const {
    const int k = size();
    za = y_.head(k);
    L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(za);
  }

  /// Solves (W_aa + eps I) x = r in place for another r (ordered like set()).
  template <typename Vector>
  void solve(Vector&& r) const {
    const int k = size();
    L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(r);
    L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(r);
  }

 private:
  using FactorStore = LcpWorkspace::FactorStore;
  static FactorStore& factorStore(LcpWorkspace* workspace, Eigen::Index c) {
    FactorStore& store = workspace->store();
    if (store.L.rows() < c) {
      const Eigen::Index grown = std::max(c, store.L.rows() + store.L.rows() / 4);
      store.L.conservativeResize(grown, grown);
    }
    return store;
  }

  /// Starts from the factor the last solve kept (keep), where the entries
  /// of W it factorises are unchanged for most of its set: the activation
  /// loop's next loop keeps most rows of H, and with them W's entries
  /// among them, and its warm start is the last loop's active set. Its rows
  /// that are not in init, or whose entries changed, are removed (Givens,
  /// O(k^2) each), then init's others added: O(k^2) a change instead of the
  /// O(k^3 / 3) of a fresh factorisation. False (nothing done) where the
  /// factor is gone, its regularisation another, or a third of it changed.
  bool resume(const std::vector<int>& init) {
    if constexpr (!Columns::kWholeColumns) return false;
    // Its regularisation within a factor of two of this one's stands for
    // it (eps scales the largest diagonal entry of W, which a new row may
    // raise; the answer is refined on the factor: refineOnFactor).
    if (init.empty() || !(store_.eps <= 2.0 * eps_ && eps_ <= 2.0 * store_.eps)) return false;
    const int c = W_.size(), k0 = static_cast<int>(store_.set.size());
    std::vector<char> wanted(c, 0);
    for (int i : init) wanted[i] = 1;
    std::vector<char> stays(k0);
    for (int j = 0; j < k0; ++j) stays[j] = store_.set[j] < c && wanted[store_.set[j]];
    // A changed entry: its row or its column changed. A re-formed row
    // differs from nearly every other (its diagonal entry first): the rows
    // with the most changed entries go first, until none is left.
    std::vector<std::array<int, 2>> differ;  // (i, j) positions
    std::vector<int> count(k0, 0);
    for (int j = 0; j < k0; ++j) {
      if (!stays[j]) continue;
      const auto column = W_.col(store_.set[j]);
      if (column(store_.set[j]) != store_.entries(j, j)) {
        stays[j] = 0;
        continue;
      }
      for (int i = j + 1; i < k0; ++i)
        if (stays[i] && column(store_.set[i]) != store_.entries(i, j)) {
          differ.push_back({i, j});
          ++count[i], ++count[j];
        }
    }
    while (true) {
      int worst = -1;
      for (const auto& [i, j] : differ)
        if (stays[i] && stays[j]) {
          const int r = count[i] >= count[j] ? i : j;
          if (worst < 0 || count[r] > count[worst]) worst = r;
        }
      if (worst < 0) break;
      stays[worst] = 0;
      for (const auto& [i, j] : differ)
        if (i == worst || j == worst) --count[i == worst ? j : i];
    }
    const int removed = k0 - static_cast<int>(std::count(stays.begin(), stays.end(), 1));
    if (3 * removed > k0) return false;
    eps_ = store_.eps;
    set_ = store_.set;
    for (int p = k0 - 1; p >= 0; --p)
      if (!stays[p]) removeAt(p);
    const int k = size();
    for (int j = 0; j < k; ++j) y_(j) = b_(set_[j]);  // (b is this solve's)
    L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(y_.head(k));
    std::vector<char> in_set(c, 0);
    for (int i : set_) in_set[i] = 1;
    for (int i : init)
      if (!in_set[i]) add(i);
    resumed_ = true;
    return true;
  }

  const Columns& W_;
  const VecX& b_;
  double eps_;
  FactorStore& store_;
  Eigen::Block<MatX> L_;
  VecX row_;
  VecX y_;
  std::vector<int> set_;
  bool resumed_{false};
};

}  // namespace evsim
