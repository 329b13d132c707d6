// The still blood's viscous drag (effect 'blood_drag'). Declared and
// documented in endovascular_sim/mechanics/blood_drag.h.
#include "endovascular_sim/mechanics/blood_drag.h"

#include <algorithm>
#include <cmath>

namespace evsim {

namespace {

/// ln(L / a), at least 1: the theory is for slender rods; a short piece of a
/// device (L / a below e) gets the drag of one at L / a = e, not an
/// unbounded one.
double slenderness(double L, double a) { return std::max(1.0, std::log(L / a)); }

}  // namespace

double dragAcross(double mu, double L, double a) { return 4.0 * M_PI * mu / slenderness(L, a); }

double dragAlong(double mu, double L, double a) { return 2.0 * M_PI * mu / slenderness(L, a); }

void setBloodDrag(double mu, DeviceModel* model) {
  const int n = model->num_nodes;
  model->node_drag_across.assign(n, 0.0);
  model->node_drag_along.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double length = 0.0;  // the node's half of the elements beside it [m]
    if (i > 0) length += 0.5 * model->elements[i - 1].length;
    if (i + 1 < n) length += 0.5 * model->elements[i].length;
    const double a = model->node_radius[i];
    model->node_drag_across[i] = length * dragAcross(mu, model->length, a);
    model->node_drag_along[i] = length * dragAlong(mu, model->length, a);
  }
}

Mat3 nodeDrag(const DeviceModel& model, int i, const Vec3& tangent) {
  const double across = model.node_drag_across[i], along = model.node_drag_along[i];
  return across * Mat3::Identity() + (along - across) * tangent * tangent.transpose();
}

}  // namespace evsim
