// The C-arm's projection as a pinhole camera: the X-ray source is the
// centre of projection, the detector the image plane. The same numbers
// make the ROS CameraInfo (K, P), so standard tools back-project a pixel.
//
// Camera frame (ROS optical convention): x along the image's columns
// (right), y along its rows (down), z along the beam (source to detector).
// Pixel centres sit at whole coordinates: column i spans [i - 1/2, i + 1/2].
#pragma once

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/scene/xray_spec.h"

namespace evsim {

struct XrayCamera {
  int width{0}, height{0};                // [px]
  double fx{0.0}, fy{0.0};                // focal lengths: SID / pixel pitch [px]
  double cx{0.0}, cy{0.0};                // principal point [px] (the detector's centre)
  Mat3 rotation{Mat3::Identity()};        // scene frame -> camera frame (rows: x, y, z axes)
  Vec3 source{Vec3::Zero()};              // the focal spot, in the scene frame [m]
  double source_isocenter_distance{0.0};  // [m]
  Vec3 isocenter{Vec3::Zero()};           // [m]

  /// (u, v) [px] and depth along the beam [m] of a point of the scene frame.
  Vec3 project(const Vec3& p) const {
    const Vec3 q = rotation * (p - source);
    return {fx * q.x() / q.z() + cx, fy * q.y() / q.z() + cy, q.z()};
  }
  /// Unit direction (scene frame) of the ray from the source through (u, v).
  Vec3 ray(double u, double v) const {
    return rotation.transpose() * Vec3((u - cx) / fx, (v - cy) / fy, 1.0).normalized();
  }
  /// Camera axes in the scene frame.
  Vec3 beam() const { return rotation.row(2).transpose(); }
  /// Pixel pitch at the isocentre [m]: the detector's pitch over the magnification.
  double isocenterPixel() const { return source_isocenter_distance / fx; }
};

/// The camera of a C-arm pose around an isocentre [m] (CArmSpec's own
/// when given there).
XrayCamera cameraOf(const CArmSpec& c_arm, const Vec3& isocenter);

}  // namespace evsim
