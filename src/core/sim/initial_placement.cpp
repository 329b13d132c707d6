// Where the devices lie at the start. Declared and documented in
// endovascular_sim/sim/initial_placement.h.
#include "endovascular_sim/sim/initial_placement.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "endovascular_sim/contact/coaxial.h"

namespace evsim {
namespace {

/// The nearest centreline segment (parent -> point) to p: its child point,
/// or -1 for a centreline without segments.
int nearestSegment(const Centerline& c, const Vec3& p) {
  int best = -1;
  double best_d = 1e300;
  for (int i = 0; i < c.numPoints(); ++i) {
    const int j = c.parent[i];
    if (j < 0) continue;
    const Vec3 ab = c.position[i] - c.position[j];
    const double t = std::clamp((p - c.position[j]).dot(ab) / std::max(ab.squaredNorm(), 1e-30),
                                0.0, 1.0);
    const double d = (c.position[j] + t * ab - p).squaredNorm();
    if (d < best_d) best_d = d, best = i;
  }
  return best;
}

/// Arc length [m] of node i beyond the access point (negative: in the
/// introducer).
double beyondAccess(const DeviceModel& m, double inserted_length, int i) {
  return m.node_s[i] - (m.length - inserted_length);
}

/// Whether every node of `s` beyond arc `from` lies in the lumen: its axis
/// inside the wall (a node pressed into the wall by less than its radius
/// is pushed back by the first step's contacts, as a device at rest is).
bool insideLumen(const SceneModel& model, int device, const DeviceState& s, double from) {
  const DeviceModel& m = model.devices[device];
  for (int i = 0; i < m.num_nodes; ++i)
    if (beyondAccess(m, s.inserted_length, i) > from &&
        model.vessels->evaluate(s.position[i], 0.0).value < 0.0)
      return false;
  return true;
}

/// Lays the nodes of `s` beyond arc `from` along `path`, their frames
/// carried along the path's tangent from the node before them (the shaped
/// tip straightened: it springs back in the first steps, as in a lumen).
void layAlong(const DeviceModel& m, const InsertionPath& path, double from, DeviceState* s) {
  for (int i = 1; i < m.num_nodes; ++i) {
    const double a = beyondAccess(m, s->inserted_length, i);
    if (a <= from) continue;
    Vec3 tangent;
    s->position[i] = path.at(a, &tangent);
    const Mat3 before = s->rotation[i - 1].toRotationMatrix();
    s->rotation[i] = Quat(Quat::FromTwoVectors(before.col(0), tangent).toRotationMatrix() * before);
  }
}

}  // namespace

Vec3 InsertionPath::at(double a, Vec3* tangent) const {
  const size_t n = points.size();
  if (n < 2) {
    if (tangent) *tangent = Vec3::UnitX();
    return n ? points[0] : Vec3::Zero();
  }
  a = std::clamp(a, 0.0, arc.back());
  size_t k = std::upper_bound(arc.begin(), arc.end(), a) - arc.begin();
  k = std::clamp<size_t>(k, 1, n - 1);
  const double t = (a - arc[k - 1]) / std::max(arc[k] - arc[k - 1], 1e-30);
  if (tangent) *tangent = (points[k] - points[k - 1]).normalized();
  return points[k - 1] + t * (points[k] - points[k - 1]);
}

namespace {

/// The path from the access point over segment `seg` one way (childward:
/// toward the segment's child point), then the straightest way on.
InsertionPath walkFrom(const Centerline& c, const Introducer& intro, int seg, bool childward,
                       double length) {
  InsertionPath path;
  path.points.push_back(intro.access_point);
  path.arc.push_back(0.0);
  int at = childward ? seg : c.parent[seg];
  int from = childward ? c.parent[seg] : seg;
  std::vector<std::vector<int>> children(c.numPoints());
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.parent[i] >= 0) children[c.parent[i]].push_back(i);
  Vec3 heading = (c.position[at] - c.position[from]).normalized();
  while (true) {
    const Vec3 step = c.position[at] - path.points.back();
    path.arc.push_back(path.arc.back() + step.norm());
    path.points.push_back(c.position[at]);
    if (step.norm() > 1e-12) heading = step.normalized();
    path.end_point = at;
    if (path.length() >= length) break;
    // The straightest way on from `at`, not back where it came from.
    int next = -1;
    double straightest = -2.0;
    std::vector<int> ways = children[at];
    if (c.parent[at] >= 0) ways.push_back(c.parent[at]);
    for (int w : ways) {
      if (w == from) continue;
      const Vec3 d = c.position[w] - c.position[at];
      if (d.norm() < 1e-12) continue;
      const double straight = d.normalized().dot(heading);
      if (straight > straightest) straightest = straight, next = w;
    }
    if (next < 0) break;  // a vessel's end
    from = at;
    at = next;
  }
  return path;
}

}  // namespace

InsertionPath insertionPath(const Centerline& c, const Introducer& intro, double length) {
  const int seg = nearestSegment(c, intro.access_point);
  if (seg < 0) {
    InsertionPath none;
    none.points.push_back(intro.access_point);
    none.arc.push_back(0.0);
    return none;
  }
  // Along the segment the way the introducer points, then on; aimed nearly
  // across the vessel (within 60 degrees of it), the way with room.
  const Vec3 along = (c.position[seg] - c.position[c.parent[seg]]).normalized();
  const double aim = along.dot(intro.frame.col(0));
  InsertionPath path = walkFrom(c, intro, seg, aim >= 0.0, length);
  if (std::abs(aim) < 0.5 && path.length() < length) {
    InsertionPath other = walkFrom(c, intro, seg, aim < 0.0, length);
    if (other.length() > path.length()) path = std::move(other);
  }
  return path;
}

std::string placeDevices(const SceneModel& model, std::vector<DeviceState>* devices, int* bad) {
  devices->clear();
  for (size_t i = 0; i < model.devices.size(); ++i) {
    const DeviceModel& m = model.devices[i];
    const int outer = model.outer_of.empty() ? -1 : model.outer_of[i];
    const double inserted = model.initial_inserted_length[i];
    DeviceState s = outer >= 0 ? placeInside(m, model.introducers[i], inserted,
                                             model.initial_rotation[i], model.devices[outer],
                                             (*devices)[outer])
                               : placeDevice(m, model.introducers[i], inserted,
                                             model.initial_rotation[i]);
    // Beyond the outer device's tip, or the access point.
    const double from = outer >= 0 ? (*devices)[outer].inserted_length : 0.0;
    if (model.vessels && model.centerline && inserted > from &&
        !insideLumen(model, static_cast<int>(i), s, from)) {
      const InsertionPath path = insertionPath(*model.centerline, model.introducers[i], inserted);
      if (path.length() < inserted - 1e-9) {
        if (bad) *bad = static_cast<int>(i);
        const Centerline& c = *model.centerline;
        std::ostringstream why;
        why << inserted << " m of device '" << m.name
            << "' cannot lie inside the lumen: in its rest shape it leaves the lumen, and the "
               "vessels' path from its access point (the straightest way at each fork) ends "
               "after "
            << path.length() << " m, at the end of vessel '"
            << (path.end_point >= 0 ? c.vessel_names[c.vessel[path.end_point]] : std::string("?"))
            << "': at most " << path.length() << " m fits";
        return why.str();
      }
      layAlong(m, path, from, &s);
    }
    devices->push_back(std::move(s));
  }
  return "";
}

}  // namespace evsim
