// rviz markers of a frame: device tubes, contact points, force arrows and the
// tangent planes of the contacts drawn as small quads (the paper's Figure 1);
// and the vessel surface mesh, moved with the vessels.
#pragma once

#include <std_msgs/Header.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include "endovascular_sim/geometry/surface_mesh.h"
#include "endovascular_sim/ros/frame_snapshot.h"

namespace evsim {

struct MarkerStyle {
  double force_scale{0.1};   // arrow length per force [m/N]
  double plane_size{0.003};  // side of a tangent-plane quad [m]
  int tube_sides{8};         // polygon of a device tube's cross-section
};

/// Namespaces: "devices" (one tube per device), "targets" (each target
/// vessel's centreline, amber until reached, then green), "contacts"
/// (points), "forces" (an arrow per contact with a force), "tangent_planes"
/// (quads).
/// The array starts with a DELETEALL so that vanished contacts disappear.
visualization_msgs::MarkerArray sceneMarkers(const FrameSnapshot& frame, const MarkerStyle& style,
                                             const std_msgs::Header& header);

/// The vessel wall as one TRIANGLE_LIST; with vessel motion, each vertex is
/// moved by the field's displacement at it (field may be null: no motion).
visualization_msgs::Marker vesselMeshMarker(const SurfaceMesh& mesh, const VesselField* field,
                                            const MotionSnapshot& motion,
                                            const std_msgs::Header& header);

}  // namespace evsim
