// The lumen's curvature in the loop's QP (effect 'coaxial'), the analogue
// of the wall's (contact/wall_curvature.h) for a point of an inner device
// in its outer device's lumen.
//
// A lumen contact's plane is the lumen linearised where the point lies. The
// point lies on a circle of radius rho (the clearance) about the outer
// axis, which curves around it in the direction b = t x n across the axis
// (t the axis tangent): sliding along its plane by s takes it s^2 / (2 rho)
// beyond. A wire held bent in a pre-shaped catheter springs millimetres
// across the lumen in the free motion; planes alone let it slide along them
// in every loop, and each loop added another plane (10 loops and 150 rows a
// step for a wire at rest in `arch_navigation_headhunter`).
//
// The Hessian of the gap in the relative position p - a is b b^T / rho, so
// the Lagrangian's Hessian gains lambda / rho (J_p - J_a)^T b b^T (J_p - J_a):
// a spring of stiffness k = lambda / rho on the relative slide across the
// axis. It couples the two devices, so it cannot go into the per-device
// A + C; it is a row r = b^T (J_p - J_a) of the kind of a contact's, with a
// compliance 1 / k instead of a complementarity condition. With R the
// springs' rows, K their stiffnesses and dq_k the anchor of the loop's QP,
// the spring forces mu = -K R (dq - dq_k) and
//   dq = dq_step + A^-1 (H^T lambda + R^T mu),
//   (K^-1 + R A^-1 R^T) mu = R (dq_k - dq_step) - R A^-1 H^T lambda,
// so the contacts' problem keeps its form with
//   W <- W_HH - W_HR S^-1 W_RH,  q <- q + W_HR S^-1 e,
//   S = K^-1 + W_RR,  e = R (dq_k - dq_step).
// The springs act on the relative slide only: a catheter turned with its
// wire inside, the two moving together, feels nothing. What is left when the
// loop ends, K R (dq - dq_k), is a viscous force on the relative slide from
// the first loop's anchor x_t; the loop goes on until each slide since the
// anchor is within options.lumen_settle of rho, which bounds it to that
// fraction of the contact's force.
#include <cmath>

#include "activation_loop.h"
#include "endovascular_sim/contact/contact_point.h"

namespace evsim::activation {

namespace {

/// h . (a - b) over the free nodes of the element (held nodes do not
/// move); the difference is taken on the element's two nodes only.
double freeDot(const RowPart& p, const VecX& a, const VecX& b, int first_free_node) {
  double sum = 0.0;
  for (int node = 0; node < 2; ++node) {
    if (p.element + node < first_free_node) continue;
    const int at = 6 * (p.element + node);
    sum += p.h.segment<6>(6 * node).dot(a.segment<6>(at) - b.segment<6>(at));
  }
  return sum;
}

}  // namespace

void addLumenSprings(const ContactProblem& pb, const ContactOptions& o, const LoopState& s,
                     LoopSystem* sys, std::vector<std::vector<RowPart>>* parts) {
  sys->springs.clear();
  sys->springs.reserve(sys->c);
  if (!o.wall_curvature) {
    sys->e.resize(0);
    return;
  }
  const auto& devices = *pb.devices;
  const auto& ws = *pb.workspaces;
  for (int i = 0; i < sys->c; ++i) {
    const Contact& ct = (*s.contacts)[i];
    if (!ct.lumen || !(ct.force > 0.0)) continue;
    const double rho = -ct.separation;
    if (!(rho > 1e-7)) continue;
    const SamplePoint& sp = (*pb.samples)[ct.device][ct.sample];
    const Vec3 b = sampleTangent(s.x[ct.other_device], ct.other).cross(ct.normal);
    if (!(b.squaredNorm() > 0.25)) continue;  // (n is across the axis: |b| ~ 1)
    const Vec3 unit = b.normalized();
    const int row = sys->m + static_cast<int>(sys->springs.size());
    LumenSpring spring;
    spring.device = {ct.device, ct.other_device};
    spring.first_free_node = {ws[ct.device].first_free_node, ws[ct.other_device].first_free_node};
    spring.part[0] = {row, sp.element, contactRow(devices[ct.device], s.x[ct.device], sp, unit)};
    spring.part[1] = {row, ct.other.element,
                      -contactRow(devices[ct.other_device], s.x[ct.other_device], ct.other, unit)};
    spring.rho = rho;
    spring.k = ct.force / rho;
    sys->springs.push_back(spring);
  }
  const int r = static_cast<int>(sys->springs.size());
  sys->e.resize(r);
  for (int j = 0; j < r; ++j) {
    const LumenSpring& spring = sys->springs[j];
    sys->e(j) = 0.0;
    for (int k = 0; k < 2; ++k) {
      const int d = spring.device[k];
      (*parts)[d].push_back(spring.part[k]);
      sys->e(j) += freeDot(spring.part[k], s.anchor[d], sys->dq_step[d], spring.first_free_node[k]);
    }
  }
}

void eliminateLumenSprings(LoopSystem* sys) {
  const int m = sys->m, r = static_cast<int>(sys->springs.size());
  if (r == 0) return;
  if (sys->columns) {  // W on demand: the springs' columns only, now
    std::vector<int> springs(r);
    for (int j = 0; j < r; ++j) springs[j] = m + j;
    const MatX raw = sys->columns->rawColumns(springs);  // (m + r) x r
    MatX S = raw.bottomRows(r);
    for (int j = 0; j < r; ++j) S(j, j) += 1.0 / sys->springs[j].k;
    sys->S.compute(S);
    sys->W_HR = raw.topRows(m);
    const bool factored = sys->S.info() == Eigen::Success;  // (as below)
    sys->columns->eliminate(m, &sys->W_HR, factored ? &sys->S : nullptr);
    if (factored) sys->q.noalias() += sys->W_HR * sys->S.solve(sys->e);
    return;
  }
  const MatX full = sys->W();  // (m + r) square
  MatX S = full.bottomRightCorner(r, r);
  for (int j = 0; j < r; ++j) S(j, j) += 1.0 / sys->springs[j].k;
  sys->S.compute(S);
  sys->W_HR = full.topRightCorner(m, r);
  sys->W_sum = full.topLeftCorner(m, m);
  sys->W_device = nullptr;
  // S is positive definite (W_RR semi-definite, K^-1 > 0); should its
  // factorisation fail to round-off all the same, the loop is the paper's
  // step without the springs (their forces 0).
  if (sys->S.info() != Eigen::Success) return;
  // W_HR S^-1 W_RH = Z^T Z with Z = L^-1 W_RH (S = L L^T): a symmetric
  // rank-r update of one triangle, half the flops of the general product,
  // mirrored into the other (exactly symmetric).
  MatX Z = sys->W_HR.transpose();
  sys->S.matrixL().solveInPlace(Z);
  sys->W_sum.selfadjointView<Eigen::Lower>().rankUpdate(Z.transpose(), -1.0);
  sys->W_sum.triangularView<Eigen::StrictlyUpper>() = sys->W_sum.transpose();
  sys->q.noalias() += sys->W_HR * sys->S.solve(sys->e);
}

VecX lumenSpringForces(const LoopSystem& sys, const VecX& lambda) {
  const int r = static_cast<int>(sys.springs.size());
  if (r == 0 || sys.S.info() != Eigen::Success) return VecX::Zero(r);
  return sys.S.solve(sys.e - sys.W_HR.transpose() * lambda);
}

bool lumenSpringsSettled(const LoopSystem& sys, const LoopState& s, double settle) {
  if (!sys.springs.empty() && sys.S.info() != Eigen::Success) return true;  // (no springs)
  for (const LumenSpring& spring : sys.springs) {
    double slide = 0.0;
    for (int k = 0; k < 2; ++k) {
      const int d = spring.device[k];
      slide += freeDot(spring.part[k], s.dq[d], s.anchor[d], spring.first_free_node[k]);
    }
    if (std::abs(slide) > settle * spring.rho) return false;
  }
  return true;
}

}  // namespace evsim::activation
