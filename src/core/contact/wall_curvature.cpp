// The wall's curvature in the step's system matrix (a sequential-QP step).
// Declared and documented in endovascular_sim/contact/wall_curvature.h.
#include "endovascular_sim/contact/wall_curvature.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace evsim {

Eigen::Matrix2d wallCurvature(const ImplicitSurface& surface, const Vec3& point, const Vec3& normal,
                              double device_radius, const MotionSnapshot& motion,
                              std::array<Vec3, 2>* t, double h) {
  (*t)[0] = normal.unitOrthogonal();
  (*t)[1] = normal.cross((*t)[0]);
  // The four gradients about the point; their mean is the gradient at the
  // point to the same order, h^2, as the differences (no fifth evaluation).
  std::array<Vec3, 2> dg;
  Vec3 mean = Vec3::Zero();
  for (int a = 0; a < 2; ++a) {
    const Vec3 plus = surface.evaluate(point + h * (*t)[a], device_radius, motion).gradient;
    const Vec3 minus = surface.evaluate(point - h * (*t)[a], device_radius, motion).gradient;
    dg[a] = plus - minus;
    mean += 0.25 * (plus + minus);
  }
  const double grad = mean.norm();
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  if (!(grad > 0.0)) return S;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) S(b, a) = -(*t)[b].dot(dg[a]) / (2.0 * h * grad);
  S = 0.5 * (S + S.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
  const Eigen::Vector2d k = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * k.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace evsim
