#include "endovascular_sim/contact/friction.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace evsim {
namespace {

/// Projection on the cone |r_t| <= mu r_n.
Vec3 projectOnCone(const Vec3& r, double mu) {
  const double rt = r.tail<2>().norm();
  if (rt <= mu * r(0)) return r;
  if (mu * rt <= -r(0)) return Vec3::Zero();
  const double a = (r(0) + mu * rt) / (1.0 + mu * mu);
  return Vec3(a, mu * a * r(1) / rt, mu * a * r(2) / rt);
}

/// The sliding solution for a slip angle phi: r = r_n (1, mu e), e =
/// (cos phi, sin phi), with u_n = 0. `valid` is false when no positive r_n
/// closes the gap at this angle.
struct Slide {
  bool valid{false};
  double rn{0.0};
  Eigen::Vector2d e, ut;
  double cross{0.0};  // u_t x e: zero when u_t is parallel to e
  double along{0.0};  // u_t . e: negative when friction opposes the slip
};

Slide slideAt(const Mat3& A, const Vec3& b, double mu, double phi) {
  Slide s;
  s.e = Eigen::Vector2d(std::cos(phi), std::sin(phi));
  const double den = A(0, 0) + mu * (A(0, 1) * s.e(0) + A(0, 2) * s.e(1));
  if (!(den > 0.0)) return s;
  s.rn = -b(0) / den;
  if (!(s.rn > 0.0)) return s;
  s.ut = b.tail<2>() + s.rn * (A.block<2, 1>(1, 0) + mu * A.block<2, 2>(1, 1) * s.e);
  s.cross = s.ut(0) * s.e(1) - s.ut(1) * s.e(0);
  s.along = s.ut.dot(s.e);
  s.valid = true;
  return s;
}

Vec3 forceOf(const Slide& s, double mu) {
  return Vec3(s.rn, mu * s.rn * s.e(0), mu * s.rn * s.e(1));
}

/// The sliding angle by bracketing u_t x e on 32 angles from phi0 and
/// bisecting a sign change where u_t opposes e. False when none exists.
bool solveSliding(const Mat3& A, const Vec3& b, double mu, double phi0, Vec3* r) {
  constexpr int kSamples = 32;
  const double step = 2.0 * M_PI / kSamples;
  Slide prev = slideAt(A, b, mu, phi0);
  for (int k = 1; k <= kSamples; ++k) {
    const Slide next = slideAt(A, b, mu, phi0 + k * step);
    if (prev.valid && next.valid && (prev.cross <= 0.0) != (next.cross <= 0.0) &&
        (prev.along < 0.0 || next.along < 0.0)) {
      double lo = phi0 + (k - 1) * step, hi = phi0 + k * step;
      Slide at_lo = prev;
      for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        const Slide m = slideAt(A, b, mu, mid);
        if (!m.valid) break;
        if ((m.cross <= 0.0) == (at_lo.cross <= 0.0)) {
          lo = mid;
          at_lo = m;
        } else {
          hi = mid;
        }
      }
      const Slide s = slideAt(A, b, mu, 0.5 * (lo + hi));
      if (s.valid && s.along <= 0.0) {
        *r = forceOf(s, mu);
        return true;
      }
    }
    prev = next;
  }
  return false;
}

/// Exact solution of one contact's problem u = A r + b.
Vec3 solveLocal(const Mat3& A, const Vec3& b, double mu, const Vec3& previous) {
  if (b(0) >= 0.0) return Vec3::Zero();  // separated
  if (mu == 0.0) return Vec3(-b(0) / A(0, 0), 0.0, 0.0);
  const Vec3 stick = -A.llt().solve(b);
  if (stick(0) > 0.0 && stick.tail<2>().norm() <= mu * stick(0)) return stick;
  // Sliding: start the search at the previous force's angle, or opposite to
  // the slip that frictionless contact would give.
  double phi0;
  if (previous.tail<2>().norm() > 0.0) {
    phi0 = std::atan2(previous(2), previous(1));
  } else {
    const Eigen::Vector2d slip = b.tail<2>() - A.block<2, 1>(1, 0) * b(0) / A(0, 0);
    phi0 = std::atan2(-slip(1), -slip(0));
  }
  phi0 -= M_PI / 64.0;  // the previous angle itself mid-interval
  Vec3 r;
  if (solveSliding(A, b, mu, phi0, &r)) return r;
  return projectOnCone(stick, mu);  // degenerate block: the nearest admissible force
}

/// One Gauss-Seidel sweep: each contact's exact solution with the others'
/// forces fixed.
void gaussSeidelSweep(const MatX& W, const VecX& q, const VecX& mu, const std::vector<Mat3>& block,
                      VecX* r) {
  for (int i = 0; i < static_cast<int>(mu.size()); ++i) {
    const Vec3 ri = r->segment<3>(3 * i);
    const Vec3 b =
        q.segment<3>(3 * i) + W.middleRows<3>(3 * i) * (*r) - W.block<3, 3>(3 * i, 3 * i) * ri;
    r->segment<3>(3 * i) = solveLocal(block[i], b, mu(i), ri);
  }
}

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

/// Solves J dr = -phi where the rows of separated contacts are those of the
/// identity (D = 0): there dr_i = -phi_i, and only the other contacts'
/// block is factorised, J_AA dr_A = -phi_A - J_AS dr_S. Most candidate
/// contacts are separated, so this is the status method's saving: the same
/// step, a much smaller factorisation.
VecX newtonStep(const MatX& J, const VecX& phi, const std::vector<char>& separated) {
  std::vector<int> free, fixed;  // DOF indices of non-separated / separated contacts
  for (size_t i = 0; i < separated.size(); ++i)
    for (int k = 0; k < 3; ++k)
      (separated[i] ? fixed : free).push_back(3 * static_cast<int>(i) + k);
  VecX dr(phi.size());
  for (int j : fixed) dr(j) = -phi(j);
  if (free.empty()) return dr;
  const int m = static_cast<int>(free.size());
  MatX Jaa(m, m);
  VecX rhs(m);
  for (int a = 0; a < m; ++a) {
    double b = -phi(free[a]);
    for (int j : fixed) b -= J(free[a], j) * dr(j);
    rhs(a) = b;
    for (int k = 0; k < m; ++k) Jaa(a, k) = J(free[a], free[k]);
  }
  const VecX da = Jaa.partialPivLu().solve(rhs);
  for (int a = 0; a < m; ++a) dr(free[a]) = da(a);
  return dr;
}

/// The status method for friction: semismooth Newton on the Alart-Curnier
/// function, J dr = -phi with J = I - D (I - rho W) (D from each contact's
/// status), and a backtracking line search on |phi|^2. Steps that stall fall
/// back to one Gauss-Seidel sweep. eps = 1e-12 max diag W.
LcpStatus solveNewton(const MatX& W, const VecX& q, const VecX& mu, const std::vector<Mat3>& block,
                      double eps, int max_steps, const FrictionOptions& o, VecX* r,
                      FrictionStats* st) {
  const int c = static_cast<int>(mu.size()), n = 3 * c;
  // The Jacobian of sticking contacts is rho W: singular for redundant
  // contacts (a thread wrapped on a cylinder: cond W ~ 1e17). The step is
  // taken with W + shift I (shift = 1e-8 max diag W), which bounds it; phi
  // and the residual use W itself, so the solution is not changed.
  const double shift = 1e4 * eps;
  VecX rho_n(c), rho_t(c);
  for (int i = 0; i < c; ++i) {
    rho_n(i) = 1.0 / block[i](0, 0);
    rho_t(i) = 2.0 / (block[i](1, 1) + block[i](2, 2));
  }
  std::vector<char> separated(c);  // D = 0: that block's row of J is the identity's
  auto evaluate = [&](const VecX& x, VecX* phi, MatX* J) {
    const VecX u = W * x + q;
    if (J) J->setZero(n, n);
    for (int i = 0; i < c; ++i) {
      const AcBlock b =
          alartCurnier(x.segment<3>(3 * i), u.segment<3>(3 * i), mu(i), rho_n(i), rho_t(i));
      phi->segment<3>(3 * i) = b.phi;
      if (!J) continue;
      separated[i] = b.D.isZero(0.0);
      // Rows of block i: I - D (E_i - rho W_i) = (I - D) E_i + D rho W_i.
      Mat3 Drho = b.D;
      Drho.col(0) *= rho_n(i);
      Drho.col(1) *= rho_t(i);
      Drho.col(2) *= rho_t(i);
      J->middleRows<3>(3 * i) = Drho * W.middleRows<3>(3 * i);
      J->block<3, 3>(3 * i, 3 * i) += Mat3::Identity() - b.D + shift * Drho;
    }
  };
  VecX phi(n), trial_phi(n);
  MatX J;
  for (int steps = 0; steps < max_steps; ++steps) {
    ++st->sweeps;
    evaluate(*r, &phi, &J);
    const double merit = phi.squaredNorm();
    const VecX dr = newtonStep(J, phi, separated);
    double alpha = 1.0;
    bool accepted = false;
    if (dr.allFinite()) {
      for (int k = 0; k < 30; ++k, alpha *= 0.5) {
        const VecX trial = *r + alpha * dr;
        evaluate(trial, &trial_phi, nullptr);
        if (trial_phi.squaredNorm() <= (1.0 - 1e-4 * alpha) * merit) {
          *r = trial;
          accepted = true;
          break;
        }
      }
    }
    if (!accepted) gaussSeidelSweep(W, q, mu, block, r);
    st->residual = frictionResidual(W, q, mu, *r);
    if (!std::isfinite(st->residual)) return LcpStatus::kFailed;
    if (st->residual <= o.tolerance) return LcpStatus::kSolved;
  }
  return LcpStatus::kIterationLimit;
}

}  // namespace

FrictionSolver frictionSolverFromName(const std::string& name) {
  if (name == "newton") return FrictionSolver::kNewton;
  if (name == "nsgs") return FrictionSolver::kNsgs;
  throw std::invalid_argument("unknown friction solver '" + name + "' (known: newton, nsgs)");
}

const char* frictionSolverName(FrictionSolver solver) {
  return solver == FrictionSolver::kNewton ? "newton" : "nsgs";
}

double frictionResidual(const MatX& W, const VecX& q, const VecX& mu, const VecX& r) {
  const VecX u = W * r + q;
  double sum = 0.0;
  for (int i = 0; i < mu.size(); ++i) {
    const Vec3 ri = r.segment<3>(3 * i);
    Vec3 uh = u.segment<3>(3 * i);
    uh(0) += mu(i) * uh.tail<2>().norm();
    sum += (ri - projectOnCone(ri - uh, mu(i))).squaredNorm();
  }
  const double nq = q.norm();
  return nq > 0.0 ? std::sqrt(sum) / nq : std::sqrt(sum);
}

LcpStatus solveFrictionalContact(const MatX& W, const VecX& q, const VecX& mu,
                                 const FrictionOptions& o, VecX* r, FrictionStats* stats) {
  const int c = static_cast<int>(mu.size());
  if (r->size() != 3 * c || !r->allFinite()) r->setZero(3 * c);
  FrictionStats st;
  const double eps = 1e-12 * (c ? W.diagonal().maxCoeff() : 0.0);
  std::vector<Mat3> block(c);
  for (int i = 0; i < c; ++i) block[i] = W.block<3, 3>(3 * i, 3 * i) + eps * Mat3::Identity();
  LcpStatus status = LcpStatus::kIterationLimit;
  st.residual = frictionResidual(W, q, mu, *r);
  if (c == 0 || st.residual <= o.tolerance) {
    status = LcpStatus::kSolved;
  } else if (o.solver == FrictionSolver::kNewton) {
    // From the warm start first; Newton with a line search on the
    // non-smooth |phi|^2 can stall far from the solution (seen on the
    // capstan, from a previous loop's forces), then once more from zero.
    const int warm_steps = std::max(1, o.max_sweeps / 4);
    status = solveNewton(W, q, mu, block, eps, warm_steps, o, r, &st);
    if (status == LcpStatus::kIterationLimit && o.max_sweeps > warm_steps) {
      r->setZero(3 * c);
      status = solveNewton(W, q, mu, block, eps, o.max_sweeps - warm_steps, o, r, &st);
    }
  } else {
    while (status != LcpStatus::kSolved && st.sweeps < o.max_sweeps) {
      ++st.sweeps;
      gaussSeidelSweep(W, q, mu, block, r);
      st.residual = frictionResidual(W, q, mu, *r);
      if (!std::isfinite(st.residual)) status = LcpStatus::kFailed;
      if (st.residual <= o.tolerance) status = LcpStatus::kSolved;
      if (status == LcpStatus::kFailed) break;
    }
  }
  if (status == LcpStatus::kFailed) r->setZero(3 * c);
  for (int i = 0; i < c; ++i) {
    const Vec3 ri = r->segment<3>(3 * i);
    if (ri(0) <= 0.0) continue;
    if (ri.tail<2>().norm() < mu(i) * ri(0) * (1.0 - 1e-9))
      ++st.sticking;
    else
      ++st.sliding;
  }
  if (stats) *stats = st;
  return status;
}

}  // namespace evsim
