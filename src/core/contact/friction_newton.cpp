// The status method extended to friction: semismooth Newton on the
// Alart-Curnier function (see friction.h).
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "friction_local.h"

namespace evsim {
namespace friction {
namespace {

/// The line search accepts a step that lowers |phi|^2 below the largest of
/// the last kMemory Newton iterates' (Grippo, Lampariello and Lucidi's
/// non-monotone rule). With the monotone rule (memory 1) a step that crosses
/// several contacts' branches is cut to a few thousandths, and the solver
/// took hundreds of short steps or stalled on redundant contacts: on the
/// friction problems of `carotid_catheter`, from zero, 241 steps per problem
/// and 35 of 200 problems unsolved in 1,000 steps; non-monotone, 34 steps
/// and none unsolved (memory 3: 40, memory 20: 34).
constexpr int kMemory = 10;
constexpr int kMaxHalvings = 30;
constexpr double kSufficientDecrease = 1e-4;
/// Newton steps without a new best residual after which it gives up (the
/// caller then tries its other start, or the step is subdivided): each step
/// costs a dense solve, and a stalled Newton otherwise spends its whole
/// budget (seen: minutes on a wire in a catheter at an ostium).
constexpr int kStallSteps = 60;

/// The Alart-Curnier function of one contact and its derivative: with
/// v = r - rho u (rho = diag(rho_n, rho_t, rho_t)),
///   phi = r - P(v),  P(v) = ([v_n]_+, proj of v_t on the disc of radius
///   mu [v_n]_+),
/// D = dP/dv. phi = 0 is Coulomb's law. The three branches of P are the
/// statuses: separated (v_n <= 0), sticking (inside the disc), sliding.
struct AcBlock {
  Vec3 phi;
  Mat3 D;
};

AcBlock alartCurnier(const Vec3& r, const Vec3& u, double mu, double rho_n, double rho_t) {
  const Vec3 v(r(0) - rho_n * u(0), r(1) - rho_t * u(1), r(2) - rho_t * u(2));
  AcBlock b;
  b.D.setZero();
  Vec3 p = Vec3::Zero();
  if (v(0) > 0.0) {
    p(0) = v(0);
    b.D(0, 0) = 1.0;
    const double radius = mu * v(0);
    const Eigen::Vector2d vt = v.tail<2>();
    const double nt = vt.norm();
    if (nt <= radius) {  // sticking
      p.tail<2>() = vt;
      b.D.block<2, 2>(1, 1).setIdentity();
    } else {  // sliding
      const Eigen::Vector2d h = vt / nt;
      p.tail<2>() = radius * h;
      b.D.block<2, 2>(1, 1) = radius / nt * (Eigen::Matrix2d::Identity() - h * h.transpose());
      b.D.block<2, 1>(1, 0) = mu * h;
    }
  }
  b.phi = r - p;
  return b;
}

class NewtonSolver {
 public:
  NewtonSolver(const MatXView& W, const VecX& mu, double eps)
      : W_(W), mu_(mu), c_(static_cast<int>(mu.size())), D_(c_) {
    // The Jacobian of sticking contacts is rho W: singular for redundant
    // contacts (a thread wrapped on a cylinder: cond W ~ 1e17). The step is
    // taken with W + shift I (shift = 1e-8 max diag W), which bounds it; phi
    // and the residual use W itself, so the solution is not changed.
    shift_ = 1e4 * eps;
    rho_n_.resize(c_);
    rho_t_.resize(c_);
    for (int i = 0; i < c_; ++i) {
      rho_n_(i) = 1.0 / (W(3 * i, 3 * i) + eps);
      rho_t_(i) = 2.0 / (W(3 * i + 1, 3 * i + 1) + W(3 * i + 2, 3 * i + 2) + 2.0 * eps);
    }
  }

  /// phi at the forces r with velocities u = W r + q; with derivatives, the
  /// D of every contact too.
  void evaluate(const VecX& r, const VecX& u, VecX* phi, bool derivatives) {
    for (int i = 0; i < c_; ++i) {
      const AcBlock b =
          alartCurnier(r.segment<3>(3 * i), u.segment<3>(3 * i), mu_(i), rho_n_(i), rho_t_(i));
      phi->segment<3>(3 * i) = b.phi;
      if (derivatives) D_[i] = b.D;
    }
  }

  /// Solves J dr = -phi, J = I - D (I - rho W) with the last D. The rows of
  /// separated contacts (D = 0) are the identity's: there dr_i = -phi_i, and
  /// only the other contacts' block is formed and factorised,
  ///   J_AA dr_A = -phi_A - J_AS dr_S,  J_AS = D_A rho_A W_AS.
  /// Most candidate contacts are separated, so this is the status method's
  /// saving: the same step, a much smaller matrix.
  VecX step(const VecX& phi) const {
    std::vector<int> active;
    for (int i = 0; i < c_; ++i)
      if (!D_[i].isZero(0.0)) active.push_back(i);
    VecX dr = -phi;
    if (active.empty()) return dr;
    VecX dr_separated = dr;
    for (int i : active) dr_separated.segment<3>(3 * i).setZero();
    const int na = static_cast<int>(active.size());
    MatX J(3 * na, 3 * na);
    VecX rhs(3 * na);
    for (int a = 0; a < na; ++a) {
      const int i = active[a];
      Mat3 Drho = D_[i];
      Drho.col(0) *= rho_n_(i);
      Drho.col(1) *= rho_t_(i);
      Drho.col(2) *= rho_t_(i);
      const Vec3 coupling = W_.middleRows<3>(3 * i) * dr_separated;
      rhs.segment<3>(3 * a) = -phi.segment<3>(3 * i) - Drho * coupling;
      for (int b = 0; b < na; ++b)
        J.block<3, 3>(3 * a, 3 * b) = Drho * W_.block<3, 3>(3 * i, 3 * active[b]);
      J.block<3, 3>(3 * a, 3 * a) += Mat3::Identity() - D_[i] + shift_ * Drho;
    }
    const VecX da = J.partialPivLu().solve(rhs);
    for (int a = 0; a < na; ++a) dr.segment<3>(3 * active[a]) = da.segment<3>(3 * a);
    return dr;
  }

 private:
  MatXView W_;
  const VecX& mu_;
  int c_;
  double shift_{0.0};
  VecX rho_n_, rho_t_;
  std::vector<Mat3> D_;
};

}  // namespace

LcpStatus solveNewton(const MatXView& W, const VecX& q, const VecX& mu,
                      const std::vector<Mat3>& block, double eps, int max_steps, double tolerance,
                      VecX* r, FrictionStats* st) {
  const int n = static_cast<int>(q.size());
  NewtonSolver newton(W, mu, eps);
  VecX u(n), phi(n), trial(n), trial_u(n), trial_phi(n);
  std::deque<double> recent;  // |phi|^2 of the last kMemory iterates
  double best = std::numeric_limits<double>::infinity();
  int best_step = 0;
  for (int k = 0;; ++k) {
    u.noalias() = W * (*r);
    u += q;
    st->residual = residualAt(q, mu, *r, u);
    if (!std::isfinite(st->residual)) return LcpStatus::kFailed;
    if (st->residual <= tolerance) return LcpStatus::kSolved;
    if (st->residual < 0.5 * best) {
      best = st->residual;
      best_step = k;
    }
    if (k == max_steps || k - best_step > kStallSteps) return LcpStatus::kIterationLimit;
    ++st->sweeps;
    newton.evaluate(*r, u, &phi, /*derivatives=*/true);
    const double merit = phi.squaredNorm();
    recent.push_back(merit);
    if (static_cast<int>(recent.size()) > kMemory) recent.pop_front();
    const double reference = *std::max_element(recent.begin(), recent.end());
    const VecX dr = newton.step(phi);
    bool accepted = false;
    if (dr.allFinite()) {
      const VecX Wdr = W * dr;  // the trial velocities are then O(n) each
      double alpha = 1.0;
      for (int h = 0; h < kMaxHalvings && !accepted; ++h, alpha *= 0.5) {
        trial = *r + alpha * dr;
        trial_u = u + alpha * Wdr;
        newton.evaluate(trial, trial_u, &trial_phi, /*derivatives=*/false);
        if (trial_phi.squaredNorm() <= reference - kSufficientDecrease * alpha * merit) {
          r->swap(trial);
          accepted = true;
        }
      }
    }
    if (!accepted) gaussSeidelSweep(W, q, mu, block, r);  // a step that stalls
  }
}

}  // namespace friction
}  // namespace evsim
