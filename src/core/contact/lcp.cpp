// Linear complementarity problems of the contact space: find z >= 0 with w = W
// z + q >= 0 and z . Declared and documented in
// endovascular_sim/contact/lcp.h.
#include "endovascular_sim/contact/lcp.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "active_cholesky.h"

namespace evsim {
namespace {

/// W as the status method reads it: whole columns and the largest diagonal
/// entry. Dense: a matrix. On demand: a ColumnOperator, whose columns are
/// formed when first read.
struct DenseColumns {
  static constexpr bool kWholeColumns = true;  // every column at hand (mostViolatedWatched)
  const MatXView& W;
  int size() const { return static_cast<int>(W.rows()); }
  auto col(int j) const { return W.col(j); }
  double maxDiagonal() const { return W.diagonal().maxCoeff(); }
};

struct ColumnsOnDemand {
  static constexpr bool kWholeColumns = false;  // an inactive row's column is not formed
  ColumnOperator& W;
  int size() const { return W.size(); }
  Eigen::Map<const VecX> col(int j) const { return W.column(j); }
  double maxDiagonal() const { return W.maxDiagonal(); }
};

/// w = W z + q for z zero outside the active set (z_a ordered like `set`):
/// O(c k) column sweeps instead of a full product.
template <typename Columns>
void gapsOfActive(const Columns& W, const VecX& q, const std::vector<int>& set,
                  const Eigen::Ref<const VecX>& za, VecX* w) {
  *w = q;
  const size_t k = set.size();
  size_t j = 0;
  for (; j + 4 <= k; j += 4)  // four columns a pass: w read and written a quarter as often
    w->noalias() += W.col(set[j]) * za(j) + W.col(set[j + 1]) * za(j + 1) +
                    W.col(set[j + 2]) * za(j + 2) + W.col(set[j + 3]) * za(j + 3);
  for (; j < k; ++j) w->noalias() += W.col(set[j]) * za(j);
}

/// The most violated (w_i < -tolerance) of the watched inactive rows, or
/// -1: w_i = q_i + W_ia z_a, k products instead of the c k of every gap
/// (dense: from row i's own column, W being symmetric, dotted with z_a
/// scattered into the scratch *z of size c). Rows no longer violated (or
/// active) leave the watch.
template <typename Columns>
int mostViolatedWatched(const Columns& W, const VecX& q, const std::vector<int>& set,
                        const Eigen::Ref<const VecX>& za, const std::vector<char>& active,
                        double tolerance, std::vector<int>* watched, VecX* z) {
  int add = -1;
  double lowest = -tolerance;
  if (watched->empty()) return add;
  const size_t k = set.size();
  if constexpr (Columns::kWholeColumns) {
    z->setZero();
    for (size_t j = 0; j < k; ++j) (*z)(set[j]) = za(j);
  }
  size_t kept = 0;
  for (const int i : *watched) {
    if (active[i]) continue;
    double wi = q(i);
    if constexpr (Columns::kWholeColumns) {
      wi += W.col(i).dot(*z);  // (row i, contiguous)
    } else {  // an inactive row's own column is not formed: row i of the active columns
      for (size_t j = 0; j < k; ++j) wi += W.col(set[j])(i) * za(j);
    }
    if (!(wi < -tolerance)) continue;
    (*watched)[kept++] = i;
    if (wi < lowest) {
      lowest = wi;
      add = i;
    }
  }
  watched->resize(kept);
  return add;
}

/// |z - max(0, z - w)| / |q| for z zero outside the active set.
double residualOfActive(const VecX& q, const std::vector<int>& set,
                        const Eigen::Ref<const VecX>& za, const VecX& w,
                        const std::vector<char>& active) {
  double r2 = 0.0;
  for (size_t j = 0; j < set.size(); ++j) {
    const double r = za(j) - std::max(0.0, za(j) - w(set[j]));
    r2 += r * r;
  }
  for (int i = 0; i < q.size(); ++i)
    if (!active[i] && w(i) < 0.0) r2 += w(i) * w(i);
  const double nq = q.norm();
  return nq > 0.0 ? std::sqrt(r2) / nq : std::sqrt(r2);
}

/// Iterative refinement of the active set's forces za (gaps *w) on the same
/// factor: removes the bias of the regularisation (eps z) and the round-off
/// of many factor updates; a refined za is kept only while it stays
/// non-negative and lowers the residual. Not tried once the residual is at
/// round-off level. Returns the residual.
template <typename Columns>
double refineOnFactor(const Columns& W, const VecX& q, const ActiveCholesky<Columns>& chol,
                      const std::vector<char>& active, Eigen::Ref<VecX> za, VecX* w) {
  constexpr double kRoundOff = 64 * std::numeric_limits<double>::epsilon();
  const int k = chol.size();
  double best = residualOfActive(q, chol.set(), za, *w, active);
  VecX dz(k), trial(k), trial_w(q.size());
  for (int pass = 0; pass < 3 && best > kRoundOff; ++pass) {
    for (int j = 0; j < k; ++j) dz(j) = -(*w)(chol.set()[j]);
    chol.solve(dz);
    trial = za + dz;
    if (trial.minCoeff() < 0.0) break;
    gapsOfActive(W, q, chol.set(), trial, &trial_w);
    const double r = residualOfActive(q, chol.set(), trial, trial_w, active);
    if (!(r < best)) break;
    za = trial;
    w->swap(trial_w);
    best = r;
  }
  return best;
}

/// The status method, its factor started from the last solve's where
/// `may_resume` and that pays (ActiveCholesky::reset).
template <typename Columns>
LcpStatus statusMethodOnce(const Columns& W, const VecX& q, const LcpOptions& o, VecX* z,
                           LcpStats* st, bool may_resume, LcpWorkspace* workspace) {
  const int c = static_cast<int>(q.size());
  const double eps = o.regularization * std::max(W.maxDiagonal(), 0.0);
  const int limit = o.max_iterations > 0 ? o.max_iterations : 20 * c + 100;
  const VecX minus_q = -q;
  ActiveCholesky<Columns> chol(W, minus_q, eps, workspace);
  std::vector<char> active(c, 0);
  // Start from the empty set, or (the paper's start) from every contact
  // violated by the free motion, most violated first.
  std::vector<int> order;
  if (z->size() == c) {
    for (int i = 0; i < c; ++i)
      if ((*z)(i) > 0.0) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return (*z)(a) > (*z)(b); });
  } else if (o.start_from_violated) {
    order.reserve(c);
    for (int i = 0; i < c; ++i)
      if (q(i) < -o.tolerance) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return q(a) < q(b); });
  }
  chol.reset(order, may_resume);
  st->resumed = chol.resumed();
  for (int i : chol.set()) active[i] = 1;

  z->setZero(c);
  VecX za_store(c), w(c);
  // Partial pricing: the rows violated at the last evaluation of every gap
  // are watched, and activation takes the most violated of them while one
  // is; every gap is evaluated again only when none is (and at the end,
  // which asks that no row be violated). A warm start's first loop of a
  // packed coil swaps some 50 of 130 forces, each swap once cost all c k
  // gaps.
  std::vector<int> watched;
  VecX z_full(Columns::kWholeColumns ? c : 0);
  for (int it = 0; it < limit; ++it) {
    st->iterations = it;
    const bool murty = it >= 3 * c;
    st->switched_rule |= murty;
    const int k = chol.size();
    auto za = za_store.head(k);
    chol.solution(za);
    // I) Deactivation: the most negative force (or the lowest index, Murty).
    int drop = -1;
    for (int j = 0; j < k; ++j)
      if (za(j) < 0.0 &&
          (drop < 0 || (murty ? chol.set()[j] < chol.set()[drop] : za(j) < za(drop))))
        drop = j;
    if (drop >= 0) {
      active[chol.set()[drop]] = 0;
      chol.removeAt(drop);
      ++st->deactivations;
      continue;
    }
    // II) Activation: the most violated inactive contact (of the watched
    // ones while one is).
    int add = -1;
    if (!murty)
      add = mostViolatedWatched(W, q, chol.set(), za, active, o.tolerance, &watched, &z_full);
    if (add < 0) {
      gapsOfActive(W, q, chol.set(), za, &w);
      ++st->gap_sweeps;
      watched.clear();
      for (int i = 0; i < c; ++i) {
        if (active[i] || !(w(i) < -o.tolerance)) continue;
        watched.push_back(i);
        if (add < 0 || (murty ? i < add : w(i) < w(add))) add = i;
      }
    }
    if (add < 0) {
      const double best = refineOnFactor(W, q, chol, active, za, &w);
      st->residual = best;
      chol.keep();  // (the next loop's solve may start from it)
      for (int j = 0; j < k; ++j) (*z)(chol.set()[j]) = za(j);
      // Above the limit the answer is the regularised problem's only, and
      // said so; the caller decides what it is worth: the hard coil steps
      // of aneurysm_coiling pass through activation loops whose LCPs end at
      // residuals up to 0.11 and converge later, so a loop goes on from it,
      // but a step never ends on it.
      return best <= kLcpResidualLimit ? LcpStatus::kSolved : LcpStatus::kUnsolved;
    }
    if (!chol.add(add)) return LcpStatus::kFailed;
    active[add] = 1;
    ++st->activations;
  }
  st->iterations = limit;
  return LcpStatus::kIterationLimit;
}

/// The status method. A factor resumed from the last solve carries the
/// round-off of that solve's updates too: where its answer is not at
/// round-off level (a natural residual above 1e-12 of |q|), the problem is
/// solved again from a fresh factor, as without the resumption (a
/// safeguard: over 300 steps of the packed coil from t = 14.4 s, 1 of 301
/// resumed solves ended above it, at 2.5e-10, and its fresh solve there too).
template <typename Columns>
LcpStatus statusMethod(const Columns& W, const VecX& q, const LcpOptions& o, VecX* z, LcpStats* st,
                       LcpWorkspace* given) {
  LcpWorkspace local;  // without one: a fresh factor, nothing kept
  LcpWorkspace* workspace = given ? given : &local;
  constexpr double kResumedResidual = 1e-12;
  const VecX start = *z;
  const LcpStatus status = statusMethodOnce(W, q, o, z, st, true, workspace);
  if (!st->resumed || (status == LcpStatus::kSolved && st->residual <= kResumedResidual))
    return status;
  *z = start;
  LcpStats fresh;
  const LcpStatus again = statusMethodOnce(W, q, o, z, &fresh, false, workspace);
  fresh.iterations += st->iterations;  // (both solves' pivots)
  *st = fresh;
  return again;
}

LcpStatus pgs(const MatXView& W, const VecX& q, const LcpOptions& o, VecX* z, LcpStats* st) {
  const int c = static_cast<int>(q.size());
  const int limit = o.max_iterations > 0 ? o.max_iterations : 1000;
  z->setZero(c);
  for (int it = 1; it <= limit; ++it) {
    double change = 0.0;
    for (int i = 0; i < c; ++i) {
      if (W(i, i) <= 0.0) continue;
      const double wi = W.row(i).dot(*z) + q(i);
      const double next = std::max(0.0, (*z)(i)-wi / W(i, i));
      change = std::max(change, std::abs(next - (*z)(i)) * W(i, i));
      (*z)(i) = next;
    }
    st->iterations = it;
    if (change <= o.tolerance) return LcpStatus::kSolved;
  }
  return LcpStatus::kIterationLimit;
}

/// Re-solves W_aa z_a = -q_a exactly on the support a of z (Lemke's
/// answer, read off a tableau that carries the round-off of every pivot);
/// keeps the result when it lowers the natural residual.
void polishSupport(const MatXView& W, const VecX& q, VecX* z) {
  const int c = static_cast<int>(q.size());
  std::vector<int> a;
  for (int i = 0; i < c; ++i)
    if ((*z)(i) > 0.0) a.push_back(i);
  if (a.empty()) return;
  MatX Waa(a.size(), a.size());
  VecX qa(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    qa(i) = -q(a[i]);
    for (size_t j = 0; j < a.size(); ++j) Waa(i, j) = W(a[i], a[j]);
  }
  const VecX za = Waa.fullPivLu().solve(qa);
  VecX polished = VecX::Zero(c);
  for (size_t i = 0; i < a.size(); ++i) polished(a[i]) = std::max(0.0, za(i));
  if (za.allFinite() && lcpResidual(W, q, polished) < lcpResidual(W, q, *z)) *z = polished;
}

/// Lemke's method on the tableau [I, -W, -d | q] (w - W z - d z0 = q).
LcpStatus lemke(const MatXView& W, const VecX& q, const LcpOptions& o, VecX* z, LcpStats* st) {
  const int c = static_cast<int>(q.size());
  z->setZero(c);
  if (c == 0 || q.minCoeff() >= 0.0) return LcpStatus::kSolved;
  const int limit = o.max_iterations > 0 ? o.max_iterations : 20 * c + 100;
  // The pivot and tie thresholds are absolute: the tableau is built on W and
  // q scaled to unit largest entries (W [m/N] and q [m] span many decades
  // between scenes), and z scaled back at the end.
  const double w_scale = std::max(W.diagonal().maxCoeff(), 1e-300);
  const double q_scale = q.cwiseAbs().maxCoeff();
  // Columns: 0..c-1 w, c..2c-1 z, 2c z0; last column the right-hand side.
  MatX T(c, 2 * c + 2);
  T.setZero();
  T.leftCols(c).setIdentity();
  T.middleCols(c, c) = -W / w_scale;
  T.col(2 * c).setConstant(-1.0);
  T.col(2 * c + 1) = q / q_scale;
  std::vector<int> basis(c);
  for (int i = 0; i < c; ++i) basis[i] = i;
  auto pivot = [&](int row, int col) {
    T.row(row) /= T(row, col);
    for (int r = 0; r < c; ++r)
      if (r != row && T(r, col) != 0.0) T.row(r) -= T(r, col) * T.row(row);
    basis[row] = col;
  };
  int row;
  q.minCoeff(&row);
  int leaving = basis[row];
  pivot(row, 2 * c);  // z0 enters
  for (int it = 1; it <= limit; ++it) {
    st->iterations = it;
    const int entering = leaving < c ? leaving + c : leaving - c;  // complement
    int best = -1;
    double ratio = 0.0;
    // Ties (a degenerate q: every point of a wire dropping onto one plane
    // has the same gap) are broken lexicographically on the rows of the
    // basis inverse (the tableau's first c columns), which keeps Lemke from
    // cycling into a ray; z0 leaves whenever it ties.
    auto lexicographicallySmaller = [&](int r, int b) {
      for (int j = 0; j < c; ++j) {
        const double u = T(r, j) / T(r, entering), v = T(b, j) / T(b, entering);
        if (std::abs(u - v) > 1e-14 * std::max(1.0, std::max(std::abs(u), std::abs(v))))
          return u < v;
      }
      return false;
    };
    for (int r = 0; r < c; ++r) {
      if (T(r, entering) <= 1e-12) continue;
      const double t = T(r, 2 * c + 1) / T(r, entering);
      const bool tie = best >= 0 && std::abs(t - ratio) <= 1e-14;
      if (best < 0 || (!tie && t < ratio) ||
          (tie && basis[best] != 2 * c &&
           (basis[r] == 2 * c || lexicographicallySmaller(r, best)))) {
        best = r;
        ratio = t;
      }
    }
    if (best < 0) return LcpStatus::kInfeasible;  // ray termination
    leaving = basis[best];
    pivot(best, entering);
    if (leaving == 2 * c) {
      for (int r = 0; r < c; ++r)
        if (basis[r] >= c && basis[r] < 2 * c)
          (*z)(basis[r] - c) = std::max(0.0, T(r, 2 * c + 1)) * q_scale / w_scale;
      polishSupport(W, q, z);
      // The tableau accumulates round-off over hundreds of pivots (a 673-row
      // LCP of large_step ends at residual 0.29, its support wrong): say so
      // rather than return a wrong answer.
      return lcpResidual(W, q, *z) <= kLcpResidualLimit ? LcpStatus::kSolved : LcpStatus::kFailed;
    }
  }
  return LcpStatus::kIterationLimit;
}

}  // namespace

LcpSolver lcpSolverFromName(const std::string& name) {
  if (name == "status") return LcpSolver::kStatusMethod;
  if (name == "pgs") return LcpSolver::kPgs;
  if (name == "lemke") return LcpSolver::kLemke;
  throw std::invalid_argument("unknown LCP solver '" + name + "' (status, pgs, lemke)");
}

const char* lcpSolverName(LcpSolver solver) {
  switch (solver) {
    case LcpSolver::kStatusMethod:
      return "status";
    case LcpSolver::kPgs:
      return "pgs";
    default:
      return "lemke";
  }
}

double lcpResidual(const MatXView& W, const VecX& q, const VecX& z) {
  if (q.size() == 0) return 0.0;
  const VecX w = W * z + q;
  const VecX r = z - (z - w).cwiseMax(0.0);
  const double nq = q.norm();
  return nq > 0.0 ? r.norm() / nq : r.norm();
}

namespace {

/// What both entry points share: the stats reset, the empty problem, and a
/// failed or non-finite answer returned as zero forces with kFailed.
template <typename Solve>
LcpStatus solveGuarded(const VecX& q, VecX* z, LcpStats* st, Solve&& solve) {
  *st = LcpStats{};
  if (q.size() == 0) {  // nothing to solve (W.diagonal() of an empty W has no max)
    z->resize(0);
    return LcpStatus::kSolved;
  }
  LcpStatus status = solve();
  if (status == LcpStatus::kFailed || !z->allFinite()) {
    z->setZero(q.size());
    status = LcpStatus::kFailed;
  }
  return status;
}

}  // namespace

LcpStatus solveLcp(const MatXView& W, const VecX& q, const LcpOptions& options, VecX* z,
                   LcpStats* stats, LcpWorkspace* workspace) {
  LcpStats local;
  LcpStats* st = stats ? stats : &local;
  const LcpStatus status = solveGuarded(q, z, st, [&] {
    switch (options.solver) {
      case LcpSolver::kStatusMethod:
        return statusMethod(DenseColumns{W}, q, options, z, st, workspace);
      case LcpSolver::kPgs:
        return pgs(W, q, options, z, st);
      default:
        return lemke(W, q, options, z, st);
    }
  });
  // The status method reports the residual of its last refinement.
  const bool refined = status == LcpStatus::kSolved || status == LcpStatus::kUnsolved;
  if (!refined || options.solver != LcpSolver::kStatusMethod) st->residual = lcpResidual(W, q, *z);
  return status;
}

LcpStatus solveLcp(ColumnOperator& W, const VecX& q, const LcpOptions& options, VecX* z,
                   LcpStats* stats, LcpWorkspace* workspace) {
  LcpStats local;
  LcpStats* st = stats ? stats : &local;
  return solveGuarded(
      q, z, st, [&] { return statusMethod(ColumnsOnDemand{W}, q, options, z, st, workspace); });
}

LcpWorkspace::LcpWorkspace() = default;
LcpWorkspace::~LcpWorkspace() = default;
LcpWorkspace::LcpWorkspace(const LcpWorkspace& other)
    : store_(other.store_ ? std::make_unique<FactorStore>(*other.store_) : nullptr) {}
LcpWorkspace& LcpWorkspace::operator=(const LcpWorkspace& other) {
  if (this != &other)
    store_ = other.store_ ? std::make_unique<FactorStore>(*other.store_) : nullptr;
  return *this;
}
LcpWorkspace::LcpWorkspace(LcpWorkspace&&) noexcept = default;
LcpWorkspace& LcpWorkspace::operator=(LcpWorkspace&&) noexcept = default;

LcpWorkspace::FactorStore& LcpWorkspace::store() {
  if (!store_) store_ = std::make_unique<FactorStore>();
  return *store_;
}

}  // namespace evsim
