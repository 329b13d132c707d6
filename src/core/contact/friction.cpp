// Coulomb friction: the cone, each contact's exact local solution, the
// Gauss-Seidel sweep (NSGS) and the dispatch to the solvers (the Newton
// solver is in friction_newton.cpp).
#include "endovascular_sim/contact/friction.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "friction_local.h"

namespace evsim {
namespace friction {

Vec3 projectOnCone(const Vec3& r, double mu) {
  const double rt = r.tail<2>().norm();
  if (rt <= mu * r(0)) return r;
  if (mu * rt <= -r(0)) return Vec3::Zero();
  const double a = (r(0) + mu * rt) / (1.0 + mu * mu);
  return Vec3(a, mu * a * r(1) / rt, mu * a * r(2) / rt);
}

namespace {

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

}  // namespace

void gaussSeidelSweep(const MatXView& W, const VecX& q, const VecX& mu,
                      const std::vector<Mat3>& block, VecX* r) {
  for (int i = 0; i < static_cast<int>(mu.size()); ++i) {
    const Vec3 ri = r->segment<3>(3 * i);
    const Vec3 b =
        q.segment<3>(3 * i) + W.middleRows<3>(3 * i) * (*r) - W.block<3, 3>(3 * i, 3 * i) * ri;
    r->segment<3>(3 * i) = solveLocal(block[i], b, mu(i), ri);
  }
}

double residualAt(const VecX& q, const VecX& mu, const VecX& r, const VecX& u) {
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

namespace {

/// The frictionless answer as a start for Newton: the normal rows' LCP by
/// the status method (warm-started from the normal forces of r), with no
/// tangential force. It has the right normal active set where friction does
/// not change it, which is most contacts: from it Newton needs 9.5 steps per
/// problem on `carotid_catheter`, against 34 from zero.
VecX frictionlessForces(const MatXView& W, const VecX& q, const VecX& r) {
  const int c = static_cast<int>(q.size() / 3);
  MatX Wn(c, c);
  VecX qn(c), zn(c);
  for (int i = 0; i < c; ++i) {
    qn(i) = q(3 * i);
    zn(i) = std::max(0.0, r(3 * i));
    for (int j = 0; j < c; ++j) Wn(i, j) = W(3 * i, 3 * j);
  }
  solveLcp(Wn, qn, LcpOptions{}, &zn);  // whatever its status: only a start
  VecX start = VecX::Zero(3 * c);
  for (int i = 0; i < c; ++i) start(3 * i) = zn(i);
  return start;
}

}  // namespace
}  // namespace friction

FrictionSolver frictionSolverFromName(const std::string& name) {
  if (name == "newton") return FrictionSolver::kNewton;
  if (name == "nsgs") return FrictionSolver::kNsgs;
  throw std::invalid_argument("unknown friction solver '" + name + "' (known: newton, nsgs)");
}

const char* frictionSolverName(FrictionSolver solver) {
  return solver == FrictionSolver::kNewton ? "newton" : "nsgs";
}

double frictionResidual(const MatXView& W, const VecX& q, const VecX& mu, const VecX& r) {
  return friction::residualAt(q, mu, r, W * r + q);
}

LcpStatus solveFrictionalContact(const MatXView& W, const VecX& q, const VecX& mu,
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
    // Two starts: the forces given (the last loop's or step's) and the
    // frictionless answer; the one with the smaller residual first. Newton
    // with a line search on the non-smooth |phi|^2 can stall far from the
    // solution (seen on the capstan, from a previous loop's forces): after a
    // quarter of the steps, the other start gets the rest.
    VecX other = friction::frictionlessForces(W, q, *r);
    const double other_residual = frictionResidual(W, q, mu, other);
    if (other_residual < st.residual) {
      r->swap(other);
      st.residual = other_residual;
    }
    const int first_steps = std::max(1, o.max_sweeps / 4);
    status = friction::solveNewton(W, q, mu, block, eps, first_steps, o.tolerance, r, &st);
    if (status == LcpStatus::kIterationLimit && o.max_sweeps > first_steps) {
      r->swap(other);
      status = friction::solveNewton(W, q, mu, block, eps, o.max_sweeps - first_steps, o.tolerance,
                                     r, &st);
    }
  } else {
    while (status != LcpStatus::kSolved && st.sweeps < o.max_sweeps) {
      ++st.sweeps;
      friction::gaussSeidelSweep(W, q, mu, block, r);
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
