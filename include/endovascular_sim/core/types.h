// Eigen type aliases shared by the core library. SI units everywhere.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace evsim {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6x12 = Eigen::Matrix<double, 6, 12>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Quat = Eigen::Quaterniond;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
/// A read-only view of a column-major matrix or of a block of one (no copy).
using MatXView = Eigen::Ref<const MatX>;

}  // namespace evsim
