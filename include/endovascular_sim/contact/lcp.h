// Linear complementarity problems of the contact space:
//   find z >= 0 with w = W z + q >= 0 and z . w = 0,
// W = H A^-1 H^T the Delassus operator (symmetric positive semi-definite),
// z the contact forces lambda [N], w the gaps after correction [m].
//
// Solvers behind one interface:
//  - kStatusMethod (the paper's): solve W_aa z_a = -q_a on the active set,
//    drop the contact with the most negative force, re-solve, until z >= 0;
//    then activate the most violated inactive contact (w < -tolerance) and
//    repeat (partial pricing: the rows violated at the last evaluation of
//    every gap are watched, and the most violated of them is activated
//    while one is; every gap is evaluated again only when none is, and
//    always before the answer). By default the active set starts empty: a
//    step's rows hold many redundant candidates (neighbouring sample
//    points seeing one wall), of which few carry a force, so growing the
//    set from the most violated row needs 5-25x fewer pivots on scene LCPs
//    than the paper's start from every violated row
//    (`start_from_violated`, kept as an option).
//    The active set's Cholesky factor is updated by one row or column per
//    change (O(c^2)), never refactorised, and the forward solution
//    L^-1 b_a with it (O(k)): a pivot's re-solve is one triangular solve.
//    The next solve starts from the last one's factor where most of W's
//    entries it factorises are unchanged (the activation loop's next loop),
//    instead of factorising its warm start afresh.
//    Rank-deficient W (redundant contacts) is handled by a stated
//    regularisation: W + eps I, eps = regularization * max(diag W), which
//    makes it a P-matrix. Never cycles: after 3c pivots it switches from the
//    most-negative rule to Murty's least-index rule, which terminates for
//    P-matrices.
//  - kPgs: projected Gauss-Seidel (the method the paper improves on).
//  - kLemke: Lemke's complementary pivoting with a covering vector of ones
//    (exact up to round-off; the final basis is re-solved to polish z).
#pragma once

#include <memory>
#include <string>

#include "endovascular_sim/core/types.h"

namespace evsim {

enum class LcpSolver { kStatusMethod, kPgs, kLemke };

/// "status", "pgs", "lemke" (throws std::invalid_argument otherwise).
LcpSolver lcpSolverFromName(const std::string& name);
const char* lcpSolverName(LcpSolver solver);

struct LcpOptions {
  LcpSolver solver{LcpSolver::kStatusMethod};
  double tolerance{1e-12};          // on w >= -tolerance and PGS convergence [m]
  int max_iterations{0};            // pivots or sweeps; 0: 20 c + 100 (pivoting), 1000 (PGS)
  double regularization{1e-12};     // status method: eps / max(diag W) [-]
  bool start_from_violated{false};  // status method, without a warm start: the paper's initial
                                    // active set
};

/// kInfeasible: Lemke's method ended on a ray, which for the positive
/// semi-definite W of contacts proves that the problem has no solution.
/// kUnsolved: the status method's answer of the regularised problem W + eps
/// I (which always has one) leaves a natural residual on W above
/// kLcpResidualLimit: no solution of this problem (the contacts cannot all
/// hold, or round-off lost the support); z holds that answer and LcpStats
/// its residual. Neither is ever a step's answer: the step fails and is
/// subdivided or recovered. An activation loop may go on from a kUnsolved z
/// as an iterate (contact/contact_solver.h).
enum class LcpStatus { kSolved, kIterationLimit, kFailed, kInfeasible, kUnsolved };

/// Natural-map residual (relative to |q|) beyond which an answer is not one.
/// A right support leaves about cond(W) times the machine epsilon: 2e-9 on a
/// wire lying on a floor (cond 1e9, every gap equal); a wrong one, after
/// hundreds of pivots' round-off, 0.1-1.
constexpr double kLcpResidualLimit = 1e-6;

struct LcpStats {
  int iterations{0};          // pivots (status, Lemke) or sweeps (PGS)
  int deactivations{0};       // status method: contacts dropped for a negative force
  int activations{0};         // status method: contacts added for a negative gap
  int gap_sweeps{0};          // status method: evaluations of every gap (partial pricing: fewer
                              // than activations)
  bool switched_rule{false};  // status method: Murty's rule was needed
  bool resumed{false};        // status method: started from the last solve's factor
  double residual{0.0};       // natural-map residual |z - max(0, z - w)| / |q|
};

/// What the status method keeps from one solve to the next: its factor
/// buffer, and the factor of the last solve's active set, from which the
/// next solve starts where W's entries among that set are unchanged (the
/// activation loop's next loop: the same answer in fewer pivots). The
/// contact solver keeps one per simulation (contact/contact_workspace.h);
/// without one a solve starts afresh. A copy holds what the original holds.
class LcpWorkspace {
 public:
  struct FactorStore;  // src/core/contact/active_cholesky.h

  LcpWorkspace();
  ~LcpWorkspace();
  LcpWorkspace(const LcpWorkspace&);
  LcpWorkspace& operator=(const LcpWorkspace&);
  LcpWorkspace(LcpWorkspace&&) noexcept;
  LcpWorkspace& operator=(LcpWorkspace&&) noexcept;

  /// Created at the first use.
  FactorStore& store();

 private:
  std::unique_ptr<FactorStore> store_;
};

/// Solves the LCP (W: c x c, q: c). A z of size c is the warm start: the
/// status method starts from its rows with a positive force, largest first
/// (the previous activation loop's answer; the answer is the same, w being
/// unique, only the pivots change); pass an empty z to start cold. z is
/// then resized; on kFailed it is zero.
LcpStatus solveLcp(const MatXView& W, const VecX& q, const LcpOptions& options, VecX* z,
                   LcpStats* stats = nullptr, LcpWorkspace* workspace = nullptr);

/// W given column by column, each formed when the solver first reads it.
/// The status method reads only the columns of the rows it activates (and
/// the largest diagonal entry, for its regularisation): a problem of many
/// rows and few forces (a wire along a catheter's lumen: 250 rows, 30
/// forces) need not form the others (contact/delassus_columns.h).
class ColumnOperator {
 public:
  virtual ~ColumnOperator() = default;
  virtual int size() const = 0;
  /// Column j of W (size() entries), valid while the operator lives.
  virtual Eigen::Map<const VecX> column(int j) = 0;
  /// max_i W_ii
  virtual double maxDiagonal() = 0;
};

/// The status method on W given by columns (options.solver is not read:
/// PGS and Lemke read every entry). Same answers as on the dense W.
LcpStatus solveLcp(ColumnOperator& W, const VecX& q, const LcpOptions& options, VecX* z,
                   LcpStats* stats = nullptr, LcpWorkspace* workspace = nullptr);

/// |z - max(0, z - w)| / |q| with w = W z + q (Siconos' LCP error measure);
/// 0 for q = 0 and z = 0.
double lcpResidual(const MatXView& W, const VecX& q, const VecX& z);

}  // namespace evsim
