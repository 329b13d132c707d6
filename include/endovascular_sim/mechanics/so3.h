// Rotation group helpers. Rotation vectors are in radians; increments are
// applied on the left in the world frame: R <- exp(hat(dtheta)) R.
#pragma once

#include "endovascular_sim/core/types.h"

namespace evsim {

/// Skew matrix: hat(a) b = a x b.
Mat3 hat(const Vec3& a);

/// Rodrigues' exponential map of a rotation vector [rad].
Mat3 expSO3(const Vec3& phi);

/// The same rotation as a unit quaternion, without forming the matrix.
Quat expQuaternion(const Vec3& phi);

/// Principal logarithm, |result| <= pi [rad]. Accurate near identity.
Vec3 logSO3(const Mat3& R);

/// Right Jacobian Jr(phi): exp(phi + d) ~= exp(phi) exp(Jr(phi) d).
Mat3 rightJacobian(const Vec3& phi);

/// Inverse of the right Jacobian: log(exp(phi) exp(e)) ~= phi + JrInv(phi) e.
Mat3 rightJacobianInverse(const Vec3& phi);

}  // namespace evsim
