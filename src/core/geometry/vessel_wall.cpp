#include "endovascular_sim/geometry/vessel_wall.h"

#include <atomic>
#include <cmath>
#include <stdexcept>

#include "endovascular_sim/geometry/implicit_surface.h"

namespace evsim {

long newWallShapeVersion() {
  static std::atomic<long> versions{1};
  return versions++;
}

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

/// Adds s a a^T (x) I3 over the nodes listed: the stiffness of an energy
/// (s / 2) |sum_j a_j u_{node_j}|^2.
template <int N>
void addOuter(const int (&node)[N], const double (&a)[N], double s, Triplets* t) {
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      for (int k = 0; k < 3; ++k)
        t->emplace_back(3 * node[i] + k, 3 * node[j] + k, s * a[i] * a[j]);
}

}  // namespace

VesselWall::VesselWall(const Centerline& c, const std::vector<WallProperties>& per_vessel,
                       const std::vector<int>& held) {
  const int n = c.numPoints();
  held_.assign(n, 0);
  for (int i : held)
    if (i >= 0 && i < n) held_[i] = 1;
  length_.assign(n, 0.0);
  radius_ = c.radius;
  distensibility_.resize(n);
  damping_.assign(n, 0.0);
  std::vector<double> tether(n, 0.0);
  const auto props = [&](int i) -> const WallProperties& {
    const int v = i < static_cast<int>(c.vessel.size()) ? c.vessel[i] : 0;
    if (v < 0 || v >= static_cast<int>(per_vessel.size()))
      throw std::invalid_argument("VesselWall: no wall properties for vessel " + std::to_string(v));
    return per_vessel[v];
  };
  for (int i = 0; i < n; ++i) distensibility_[i] = props(i).distensibility;
  Triplets t;
  for (int i = 0; i < n; ++i) {
    const int p = c.parent[i];
    if (p < 0) continue;
    const Vec3 ab = c.position[i] - c.position[p];
    const double h = ab.norm();
    length_[i] += h / 2;
    length_[p] += h / 2;
    // Stretch: (EA / h) ((u_i - u_p) . t)^2 / 2, EA = 4 pi R^2 / D.
    const double r = (c.radius[i] + c.radius[p]) / 2;
    const double ea = 4 * M_PI * r * r / props(i).distensibility;
    const Vec3 axis = ab / h;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double s = ea / h * axis[a] * axis[b];
        t.emplace_back(3 * i + a, 3 * i + b, s);
        t.emplace_back(3 * p + a, 3 * p + b, s);
        t.emplace_back(3 * i + a, 3 * p + b, -s);
        t.emplace_back(3 * p + a, 3 * i + b, -s);
      }
  }
  // Bending: per parent p, point i, child j, EI |d|^2 / (h1 + h2) with
  // d = (u_j - u_i) / h2 - (u_i - u_p) / h1.
  for (int j = 0; j < n; ++j) {
    const int i = c.parent[j];
    if (i < 0 || c.parent[i] < 0) continue;
    const int p = c.parent[i];
    const double h1 = (c.position[i] - c.position[p]).norm();
    const double h2 = (c.position[j] - c.position[i]).norm();
    const double ei = 2 * M_PI * std::pow(c.radius[i], 4) / props(j).distensibility;
    const int node[3] = {p, i, j};
    const double a[3] = {1 / h1, -(1 / h1 + 1 / h2), 1 / h2};
    addOuter(node, a, 2 * ei / (h1 + h2), &t);
  }
  for (int i = 0; i < n; ++i) {
    const double k = props(i).tether_stiffness * length_[i];
    damping_[i] = props(i).tether_damping * length_[i];
    for (int a = 0; a < 3; ++a) t.emplace_back(3 * i + a, 3 * i + a, k);
  }
  // A held point: its rows and columns the identity's (its displacement 0).
  const auto free = [&](int row) { return !held_[row / 3]; };
  Triplets kept;
  for (const auto& e : t)
    if (free(e.row()) && free(e.col())) kept.push_back(e);
  for (int i = 0; i < n; ++i)
    if (held_[i])
      for (int a = 0; a < 3; ++a) kept.emplace_back(3 * i + a, 3 * i + a, 1.0);
  stiffness_.resize(3 * n, 3 * n);
  stiffness_.setFromTriplets(kept.begin(), kept.end());
}

double VesselWall::bendingStiffness(int node) const {
  return 2 * M_PI * std::pow(radius_[node], 4) / distensibility_[node];
}

double VesselWall::radiusChange(int node, double load_per_length) const {
  return distensibility_[node] * load_per_length / (4 * M_PI);
}

namespace {

VecX flat(const std::vector<Vec3>& v) {
  VecX x(3 * v.size());
  for (size_t i = 0; i < v.size(); ++i) x.segment<3>(3 * i) = v[i];
  return x;
}

void unflat(const VecX& x, std::vector<Vec3>* v) {
  v->resize(x.size() / 3);
  for (size_t i = 0; i < v->size(); ++i) (*v)[i] = x.segment<3>(3 * i);
}

}  // namespace

std::vector<Vec3> VesselWall::equilibrium(const std::vector<Vec3>& loads) const {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(stiffness_);
  VecX f = flat(loads);
  for (int i = 0; i < numNodes(); ++i)
    if (held_[i]) f.segment<3>(3 * i).setZero();
  std::vector<Vec3> u;
  unflat(ldlt.solve(f), &u);
  return u;
}

void VesselWall::step(const std::vector<Vec3>& loads, double dt, StepFactor* factor,
                      std::vector<Vec3>* displacement) const {
  const int n = numNodes();
  if (factor->dt != dt) {
    Eigen::SparseMatrix<double> a = stiffness_;
    for (int i = 0; i < n; ++i)
      if (!held_[i])
        for (int k = 0; k < 3; ++k) a.coeffRef(3 * i + k, 3 * i + k) += damping_[i] / dt;
    factor->ldlt.compute(a);
    factor->dt = dt;
  }
  if (static_cast<int>(displacement->size()) != n) displacement->assign(n, Vec3::Zero());
  VecX rhs = flat(loads);
  for (int i = 0; i < n; ++i)
    if (held_[i])
      rhs.segment<3>(3 * i).setZero();
    else
      rhs.segment<3>(3 * i) += damping_[i] / dt * (*displacement)[i];
  unflat(factor->ldlt.solve(rhs), displacement);
}

}  // namespace evsim
