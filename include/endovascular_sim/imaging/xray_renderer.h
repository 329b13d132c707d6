// Virtual fluoroscopy: the projection of a scene on the C-arm's detector
// with Beer-Lambert attenuation along each ray,
//   A(pixel) = integral of mu along the ray = sum_k mu_k L_k,
// of the soft tissue of the body (an elliptic cylinder) and its spine, the iodine in the
// vessels that hold contrast (VesselProjection) and the devices (each beam
// element a straight tube of its section's material, marker bands in
// theirs). The detector then shows I / I0 = exp(-A) (imaging/detector.h).
#pragma once

#include <vector>

#include "endovascular_sim/imaging/attenuation.h"
#include "endovascular_sim/imaging/c_arm.h"
#include "endovascular_sim/imaging/contrast.h"
#include "endovascular_sim/imaging/vessel_projection.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// Where a device is, as the renderer needs it (a copy the node's imaging
/// thread can hold while the simulation steps on).
struct DevicePose {
  std::vector<Vec3> nodes;  // [m]
  int cut_element{-1};      // a detached coil's cut element: not drawn
};

/// Line integrals of one frame, row by row.
struct XrayFrame {
  int width{0}, height{0};
  double time{0.0};                // [s] of the simulation
  std::vector<float> attenuation;  // all of it [-]
  std::vector<float> contrast;     // the iodine's part alone [-] (an angiogram's vessels)
};

struct XrayRenderStats {
  double body_ms{0.0};     // the body's chord lengths (once per camera)
  double vessels_ms{0.0};  // tracing the lumen (once per camera; per frame with moving vessels)
  double devices_ms{0.0};
  double compose_ms{0.0};      // contrast levels and the sum
  long vessel_evaluations{0};  // field evaluations of the last trace
};

class XrayRenderer {
 public:
  /// The scene's X-ray system (its `xray:` section, or the defaults); the
  /// model must outlive the renderer.
  XrayRenderer(const SceneModel& model, const XraySpec& spec);

  /// Moves the C-arm (throws std::invalid_argument naming what is out of
  /// range; the pose is then unchanged).
  void setCArm(const CArmSpec& c_arm);
  /// The detector's frame rate [1/s], noise quanta and blur [px] (throws
  /// std::invalid_argument when out of range; then unchanged).
  void setDetector(double frame_rate, double photons, double blur);
  const XrayCamera& camera() const { return camera_; }
  const XraySpec& spec() const { return spec_; }
  const AttenuationTable& coefficients() const { return mu_; }

  /// Injects contrast at a point (the catheter's tip) at `time` for
  /// `duration` [s] with the scene's concentration; returns the segments
  /// filled.
  int injectContrast(const Vec3& at, double time, double duration);
  const ContrastAgent& contrast() const { return contrast_; }

  /// The devices of a data set as poses.
  static std::vector<DevicePose> posesOf(const SimData& data);

  /// Renders a frame at simulation time [s].
  void render(const std::vector<DevicePose>& devices, double time, XrayFrame* frame);
  void render(const SimData& data, XrayFrame* frame) { render(posesOf(data), data.time, frame); }
  const XrayRenderStats& stats() const { return stats_; }
  /// The body's attenuation [-] along the central ray: what the display's
  /// automatic brightness is set to (imaging/detector.h).
  /// The body's attenuation per pixel [-] (the display's equalisation).
  const std::vector<float>& bodyAttenuation() const { return body_; }
  double referenceAttenuation() const {
    return body_[static_cast<size_t>(camera_.height / 2) * camera_.width + camera_.width / 2];
  }

 private:
  void addDevice(const DeviceModel& model, const DevicePose& pose, std::vector<float>* image) const;
  void prepareCamera();

  const SceneModel* model_;
  XraySpec spec_;
  AttenuationTable mu_;
  XrayCamera camera_;
  Vec3 default_isocenter_{Vec3::Zero()};
  ContrastAgent contrast_;
  std::vector<float> body_;   // per pixel, cached per camera
  std::vector<float> bones_;  // the spine, per pixel, cached per camera (empty: none)
  VesselProjection vessels_;
  bool vessels_traced_{false};
  XrayRenderStats stats_;
};

}  // namespace evsim
