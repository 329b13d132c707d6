// The introducer sheath's hold on the element that is leaving it. Declared and
// documented in endovascular_sim/mechanics/sheath_support.h.
#include "endovascular_sim/mechanics/sheath_support.h"

#include <algorithm>

#include "endovascular_sim/mechanics/so3.h"

namespace evsim {

SheathHold sheathHold(const DeviceModel& model, const Introducer& intro, const DeviceState& state,
                      int held) {
  SheathHold h;
  const int j = held + 1;
  if (state.released || held < 0 || j >= model.num_nodes || held == state.cut_element) return h;
  const double L = model.node_s[j] - model.node_s[held];
  const double s_a = model.length - state.inserted_length;
  const double f = std::clamp((s_a - model.node_s[held]) / L, 0.0, 1.0);
  if (!(f > 0.0)) return h;  // the clamp is at node `held`
  const BeamElementRest& rest = model.elements[held];
  const double EI = std::max(rest.bend_twist_stiffness(1), rest.bend_twist_stiffness(2));
  const double k0 = kSheathHoldFactor * 12.0 * EI / (L * L * L);
  const double k1 = kSheathHoldFactor * 4.0 * EI / L;
  const double h01 = f * f * (3.0 - 2.0 * f), h11 = f * f * (f - 1.0);
  const double d01 = 6.0 * f * (1.0 - f), d11 = f * (3.0 * f - 2.0);
  const Vec3 axis = intro.frame.col(0);
  const Mat3 P = Mat3::Identity() - axis * axis.transpose();
  const Vec3 t = state.rotation[j] * Vec3::UnitX();
  const Vec3 across = P * (state.position[j] - intro.access_point);
  const Vec3 tilt = P * t;
  const Vec3 g0 = h01 * across + h11 * L * tilt;
  const Vec3 g1 = d01 / L * across + d11 * tilt;
  Eigen::Matrix<double, 3, 6> J0, J1;
  const Mat3 Pt = -P * hat(t);  // d(P t) / d(omega): t turns by omega x t
  J0 << h01 * P, h11 * L * Pt;
  J1 << d01 / L * P, d11 * Pt;
  h.node = j;
  h.fraction = f;
  h.energy = 0.5 * (k0 * g0.squaredNorm() + k1 * g1.squaredNorm());
  h.gradient = k0 * J0.transpose() * g0 + k1 * J1.transpose() * g1;
  h.hessian = k0 * J0.transpose() * J0 + k1 * J1.transpose() * J1;
  return h;
}

}  // namespace evsim
