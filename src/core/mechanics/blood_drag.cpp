// The still blood's drag (effect 'blood_drag'). Declared and documented in
// endovascular_sim/mechanics/blood_drag.h.
#include "endovascular_sim/mechanics/blood_drag.h"

#include <algorithm>
#include <cmath>

namespace evsim {

namespace {

/// ln(L / a), at least 1: the theory is for slender rods; a short piece of a
/// device (L / a below e) gets the drag of one at L / a = e, not an
/// unbounded one.
double slenderness(double L, double a) { return std::max(1.0, std::log(L / a)); }

/// 1/2 rho d C_D(Re) speed [N s / m^2] at speed v [m/s], with form = 1/2
/// rho d [kg/m^2] and reynolds = rho d / mu [s/m] (Re = reynolds v): 1/2
/// rho d (v + 10 v^(1/3) reynolds^(-2/3)).
double cylinderDrag(double form, double reynolds, double v) {
  if (!(v > 0.0)) return 0.0;
  return form * (v + 10.0 * std::cbrt(v / (reynolds * reynolds)));
}

}  // namespace

double dragAcross(double mu, double L, double a) { return 4.0 * M_PI * mu / slenderness(L, a); }

double dragAlong(double mu, double L, double a) { return 2.0 * M_PI * mu / slenderness(L, a); }

double cylinderDragCoefficient(double re) { return 1.0 + 10.0 / std::cbrt(re * re); }

double dragAcrossAt(const Blood& blood, double L, double a, double speed) {
  const double d = 2.0 * a;
  return std::max(
      dragAcross(blood.viscosity, L, a),
      cylinderDrag(0.5 * blood.density * d, blood.density * d / blood.viscosity, speed));
}

void setBloodDrag(const Blood& blood, DeviceModel* model) {
  const int n = model->num_nodes;
  model->node_drag_across.assign(n, 0.0);
  model->node_drag_along.assign(n, 0.0);
  model->node_drag_form.assign(n, 0.0);
  model->node_drag_reynolds.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double length = 0.0;  // the node's half of the elements beside it [m]
    if (i > 0) length += 0.5 * model->elements[i - 1].length;
    if (i + 1 < n) length += 0.5 * model->elements[i].length;
    const double a = model->node_radius[i];
    model->node_drag_across[i] = length * dragAcross(blood.viscosity, model->length, a);
    model->node_drag_along[i] = length * dragAlong(blood.viscosity, model->length, a);
    model->node_drag_form[i] = length * blood.density * a;  // 1/2 rho d per unit length
    model->node_drag_reynolds[i] = 2.0 * blood.density * a / blood.viscosity;
  }
}

Mat3 nodeDrag(const DeviceModel& model, int i, const Vec3& tangent, const Vec3& velocity) {
  const double speed_across = (velocity - velocity.dot(tangent) * tangent).norm();
  const double across =
      std::max(model.node_drag_across[i],
               cylinderDrag(model.node_drag_form[i], model.node_drag_reynolds[i], speed_across));
  const double along = model.node_drag_along[i];
  return across * Mat3::Identity() + (along - across) * tangent * tangent.transpose();
}

}  // namespace evsim
