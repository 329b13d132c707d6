// rviz markers of a frame: device tubes, contact points, force arrows and the
// tangent planes of the contacts drawn as small quads (the paper's Figure 1);
// and the vessel surface mesh, moved with the vessels. Declared and documented
// in endovascular_sim/ros/scene_markers.h.
#include "endovascular_sim/ros/scene_markers.h"

#include <cmath>

#include "endovascular_sim/ros/message_conversions.h"

namespace evsim {
namespace {

std_msgs::ColorRGBA color(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const std::string& ns, int id,
                                  int type) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

void addTriangle(visualization_msgs::Marker* m, const Vec3& a, const Vec3& b, const Vec3& c) {
  m->points.push_back(toPoint(a));
  m->points.push_back(toPoint(b));
  m->points.push_back(toPoint(c));
}

/// A closed-sided tube through the nodes, its rings in the nodal frames;
/// a detached device's cut element is left open (pusher and coil apart).
visualization_msgs::Marker deviceTube(const DeviceModel& model, const DeviceState& state, int id,
                                      int sides, const std_msgs::Header& header) {
  static const std_msgs::ColorRGBA palette[] = {color(0.75f, 0.78f, 0.85f, 1.0f),
                                                color(0.20f, 0.45f, 0.90f, 1.0f),
                                                color(0.95f, 0.75f, 0.20f, 1.0f)};
  visualization_msgs::Marker m =
      marker(header, "devices", id, visualization_msgs::Marker::TRIANGLE_LIST);
  m.color = palette[id % 3];
  const size_t n = state.position.size();
  std::vector<Vec3> ring(sides), previous(sides);
  for (size_t i = 0; i < n; ++i) {
    const Mat3 R = state.rotation[i].toRotationMatrix();
    for (int k = 0; k < sides; ++k) {
      const double a = 2.0 * M_PI * k / sides;
      ring[k] = state.position[i] +
                model.node_radius[i] * (std::cos(a) * R.col(1) + std::sin(a) * R.col(2));
    }
    if (i > 0 && static_cast<int>(i) - 1 != state.cut_element) {
      for (int k = 0; k < sides; ++k) {
        const int k1 = (k + 1) % sides;
        addTriangle(&m, previous[k], ring[k], ring[k1]);
        addTriangle(&m, previous[k], ring[k1], previous[k1]);
      }
    }
    std::swap(ring, previous);
  }
  return m;
}

}  // namespace

namespace {

/// A target vessel's centreline as a thick line (an aneurysm target: its
/// dome as a sphere): amber until reached, then green.
visualization_msgs::Marker targetMarker(const SceneModel& model, size_t k, bool reached,
                                        const std_msgs::Header& header) {
  const Target& target = model.targets[k];
  if (target.vessel < 0) {
    visualization_msgs::Marker dome =
        marker(header, "targets", static_cast<int>(k), visualization_msgs::Marker::SPHERE);
    dome.pose.position = toPoint(target.center);
    dome.pose.orientation.w = 1.0;
    dome.scale.x = dome.scale.y = dome.scale.z = 2.0 * target.radius;
    dome.color = reached ? color(0.2f, 0.85f, 0.3f, 0.3f) : color(1.0f, 0.65f, 0.1f, 0.3f);
    return dome;
  }
  const NamedVessel& v = model.atlas->vessels()[target.vessel];
  visualization_msgs::Marker line =
      marker(header, "targets", static_cast<int>(k), visualization_msgs::Marker::LINE_STRIP);
  line.scale.x = std::max(0.5e-3, 0.5 * v.radius);
  line.color = reached ? color(0.2f, 0.85f, 0.3f, 0.8f) : color(1.0f, 0.65f, 0.1f, 0.8f);
  const int n = std::max(2, static_cast<int>(v.length / 0.002) + 1);
  for (int i = 0; i < n; ++i)
    line.points.push_back(toPoint(model.atlas->pointAt(target.vessel, v.length * i / (n - 1))));
  return line;
}

}  // namespace

visualization_msgs::MarkerArray sceneMarkers(const FrameSnapshot& f, const MarkerStyle& style,
                                             const std_msgs::Header& header) {
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker clear = marker(header, "", 0, visualization_msgs::Marker::CUBE);
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);

  for (size_t i = 0; i < f.devices.size(); ++i)
    array.markers.push_back(deviceTube(f.model->devices[i], f.devices[i], static_cast<int>(i),
                                       style.tube_sides, header));
  for (size_t k = 0; f.model->atlas && k < f.model->targets.size(); ++k)
    array.markers.push_back(
        targetMarker(*f.model, k, k < f.targets.size() && f.targets[k].reached, header));
  if (f.contacts.empty()) return array;

  visualization_msgs::Marker points =
      marker(header, "contacts", 0, visualization_msgs::Marker::SPHERE_LIST);
  points.scale.x = points.scale.y = points.scale.z = 0.4 * style.plane_size;
  points.color = color(1.0f, 0.9f, 0.1f, 1.0f);
  visualization_msgs::Marker planes =
      marker(header, "tangent_planes", 0, visualization_msgs::Marker::TRIANGLE_LIST);
  planes.color = color(0.2f, 0.9f, 0.3f, 0.6f);
  const double h = 0.5 * style.plane_size;
  int arrow_id = 0;
  for (const Contact& c : f.contacts) {
    points.points.push_back(toPoint(c.point));
    const Vec3 u = c.normal.unitOrthogonal(), v = c.normal.cross(u);
    const Vec3 p00 = c.point - h * u - h * v, p10 = c.point + h * u - h * v;
    const Vec3 p11 = c.point + h * u + h * v, p01 = c.point - h * u + h * v;
    addTriangle(&planes, p00, p10, p11);
    addTriangle(&planes, p00, p11, p01);
    if (c.force <= 0.0) continue;
    visualization_msgs::Marker arrow =
        marker(header, "forces", arrow_id++, visualization_msgs::Marker::ARROW);
    arrow.points.push_back(toPoint(c.point));
    arrow.points.push_back(toPoint(c.point + style.force_scale * c.force * c.normal));
    arrow.scale.x = 0.1 * style.plane_size;   // shaft diameter
    arrow.scale.y = 0.25 * style.plane_size;  // head diameter
    arrow.scale.z = 0.3 * style.plane_size;   // head length
    arrow.color = color(0.95f, 0.2f, 0.15f, 1.0f);
    array.markers.push_back(arrow);
  }
  array.markers.push_back(points);
  array.markers.push_back(planes);
  return array;
}

visualization_msgs::Marker vesselMeshMarker(const SurfaceMesh& mesh, const VesselField* field,
                                            const MotionSnapshot& motion,
                                            const std_msgs::Header& header) {
  visualization_msgs::Marker m =
      marker(header, "vessels", 0, visualization_msgs::Marker::TRIANGLE_LIST);
  m.color = color(0.85f, 0.3f, 0.3f, 0.25f);
  const bool moving = field != nullptr && !motion.empty();
  std::vector<Vec3> vertices = mesh.vertices;
  if (moving)
    for (Vec3& x : vertices) x += field->displacement(x, motion);
  m.points.reserve(3 * mesh.triangles.size());
  for (const Eigen::Vector3i& t : mesh.triangles)
    addTriangle(&m, vertices[t[0]], vertices[t[1]], vertices[t[2]]);
  return m;
}

}  // namespace evsim
