// What `evsim render` writes: the virtual fluoroscopy of a run as PNG
// frames (VTK's PNG writer), at the X-ray system's frame rate, with the
// camera's calibration for back-projection:
//   DIR/frame_NNNNN.png   mono8, row 0 at the top (the patient's head up)
//   DIR/camera_info.yaml  the projection as a ROS camera (K, P) and the
//                         C-arm's pose (source position, rotation to the
//                         camera frame) in the scene frame
//   DIR/frames.csv        per frame and device: the time, the tip's pixel
//                         (u, v), its depth along the beam and the named
//                         vessel it is in (labels for learning from images)
#pragma once

#include <fstream>
#include <string>
#include <vector>

#include "endovascular_sim/imaging/xray_renderer.h"

namespace evsim {

struct XrayRecorderOptions {
  std::string out;              // the folder (checked by the caller)
  double rate{0.0};             // frames per simulated second (0: the scene's frame_rate)
  std::vector<double> lao;      // [deg] (empty: the scene's)
  std::vector<double> cranial;  // [deg]
  int pixels{0};                // per side (0: the scene's)
  std::vector<double> inject;   // {start [s], duration [s]} of an injection, or empty
  std::string inject_device;    // at whose tip ("": the first device)
  std::string inject_vessel;    // or 5 mm into this named vessel (an aortogram's pigtail)
  bool roadmap{false};          // after the injection, its angiogram under the live image
};

class XrayRecorder {
 public:
  /// Throws std::invalid_argument for an out-of-range pose or option.
  XrayRecorder(const SceneModel& model, const XrayRecorderOptions& options);
  /// Writes the calibration and the first frame.
  bool start(const SimData& data, std::string* why);
  /// After a step: injects when due, renders and writes a frame when due.
  bool onStep(const SimData& data, std::string* why);
  /// Frames written, mean render time and its parts.
  std::string summary() const;

 private:
  bool writeFrame(const SimData& data, std::string* why);
  void writeLabels(const SimData& data);
  const SceneModel& model_;
  XrayRecorderOptions options_;
  XrayRenderer renderer_;
  int inject_device_{0};
  int inject_vessel_{-1};
  bool injected_{false};
  double period_{0.0};  // [s] between frames
  double next_frame_{0.0};
  long frames_{0};
  double render_ms_{0.0}, devices_ms_{0.0}, vessels_ms_{0.0};
  double peak_contrast_{0.0};
  std::vector<float> roadmap_;  // the angiogram at its strongest
  std::ofstream labels_;        // frames.csv
};

}  // namespace evsim
