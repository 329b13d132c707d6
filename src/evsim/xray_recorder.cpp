// What `evsim render` writes. Declared and documented in xray_recorder.h.
#include "xray_recorder.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "endovascular_sim/imaging/detector.h"

namespace evsim {

namespace {

XraySpec specOf(const SceneModel& model, const XrayRecorderOptions& o) {
  XraySpec spec = model.xray;
  if (!o.lao.empty()) spec.c_arm.lao = o.lao[0] * M_PI / 180.0;
  if (!o.cranial.empty()) spec.c_arm.cranial = o.cranial[0] * M_PI / 180.0;
  if (o.pixels > 0) spec.c_arm.pixels = o.pixels;
  if (o.rate > 0.0) spec.frame_rate = o.rate;
  return spec;
}

bool writePng(const std::string& path, int w, int h, const std::vector<std::uint8_t>& gray,
              std::string* why) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(w, h, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* out = static_cast<unsigned char*>(image->GetScalarPointer());
  // VTK's rows run from the bottom up.
  for (int v = 0; v < h; ++v)
    std::copy(gray.begin() + static_cast<long>(v) * w, gray.begin() + static_cast<long>(v + 1) * w,
              out + static_cast<long>(h - 1 - v) * w);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(image);
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    *why = "cannot write " + path;
    return false;
  }
  return true;
}

std::string matrix(int rows, int cols, const std::vector<double>& data) {
  std::ostringstream s;
  s.precision(12);
  s << "\n  rows: " << rows << "\n  cols: " << cols << "\n  data: [";
  for (size_t i = 0; i < data.size(); ++i) s << (i ? ", " : "") << data[i];
  s << "]\n";
  return s.str();
}

}  // namespace

XrayRecorder::XrayRecorder(const SceneModel& model, const XrayRecorderOptions& options)
    : model_(model), options_(options), renderer_(model, specOf(model, options)) {
  period_ = 1.0 / renderer_.spec().frame_rate;
  if (!options.inject.empty()) {
    if (options.inject.size() != 2 || !(options.inject[0] >= 0.0) || !(options.inject[1] > 0.0))
      throw std::invalid_argument("--inject needs START,DURATION [s], START >= 0, DURATION > 0");
    if (!model.vessels) throw std::invalid_argument("--inject: the scene has no vessels");
  }
  if (!options.inject_vessel.empty()) {
    inject_vessel_ = model.atlas ? model.atlas->find(options.inject_vessel) : -1;
    if (inject_vessel_ < 0)
      throw std::invalid_argument("--inject-vessel: the scene has no vessel named '" +
                                  options.inject_vessel + "' (evsim vessels SCENE lists them)");
  }
  if (!options.inject_device.empty()) {
    inject_device_ = -1;
    for (size_t d = 0; d < model.devices.size(); ++d)
      if (model.devices[d].name == options.inject_device) inject_device_ = static_cast<int>(d);
    if (inject_device_ < 0)
      throw std::invalid_argument("--inject-device: no device named '" + options.inject_device +
                                  "'");
  }
}

bool XrayRecorder::start(const SimData& data, std::string* why) {
  const XrayCamera& c = renderer_.camera();
  std::ofstream f(options_.out + "/camera_info.yaml");
  const Mat3& R = c.rotation;
  f << "# The C-arm's projection (evsim render " << model_.name << "), as a ROS camera.\n"
    << "# Scene frame -> camera frame: x_cam = rotation (x - source); pixel = K x_cam / z.\n"
    << "image_width: " << c.width << "\nimage_height: " << c.height
    << "\ncamera_name: xray\ncamera_matrix:"
    << matrix(3, 3, {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1})
    << "distortion_model: plumb_bob\ndistortion_coefficients:" << matrix(1, 5, {0, 0, 0, 0, 0})
    << "rectification_matrix:" << matrix(3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1})
    << "projection_matrix:" << matrix(3, 4, {c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0})
    << "source:" << matrix(3, 1, {c.source.x(), c.source.y(), c.source.z()}) << "rotation:"
    << matrix(3, 3,
              {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)});
  if (!f) {
    *why = "cannot write " + options_.out + "/camera_info.yaml";
    return false;
  }
  labels_.open(options_.out + "/frames.csv");
  labels_ << "frame,time_s,device,tip_u_px,tip_v_px,tip_depth_m,tip_vessel\n";
  if (!labels_) {
    *why = "cannot write " + options_.out + "/frames.csv";
    return false;
  }
  next_frame_ = data.time;
  return onStep(data, why);
}

bool XrayRecorder::onStep(const SimData& data, std::string* why) {
  if (!injected_ && !options_.inject.empty() && data.time >= options_.inject[0]) {
    const bool at_vessel = inject_vessel_ >= 0;
    const Vec3 at = at_vessel ? model_.atlas->pointAt(inject_vessel_, 0.005)
                              : data.devices[inject_device_].position.back();
    const int filled = renderer_.injectContrast(at, data.time, options_.inject[1]);
    const std::string where = at_vessel ? model_.atlas->vessels()[inject_vessel_].name
                                        : model_.devices[inject_device_].name + "'s tip";
    std::printf("t=%.3f s: contrast injected at %s for %.2f s: %d segments filled\n", data.time,
                where.c_str(), options_.inject[1], filled);
    injected_ = true;
  }
  if (data.time + 1e-12 < next_frame_) return true;
  next_frame_ += period_;
  return writeFrame(data, why);
}

bool XrayRecorder::writeFrame(const SimData& data, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  XrayFrame frame;
  renderer_.render(data, &frame);
  const double contrast = std::accumulate(frame.contrast.begin(), frame.contrast.end(), 0.0);
  if (contrast > peak_contrast_) peak_contrast_ = contrast, roadmap_ = frame.contrast;
  const bool show_roadmap = options_.roadmap && !roadmap_.empty() && contrast == 0.0;
  const std::vector<std::uint8_t> gray =
      detectorGray(frame, renderer_.spec(), renderer_.referenceAttenuation(), frames_,
                   show_roadmap ? &roadmap_ : nullptr, &renderer_.bodyAttenuation());
  render_ms_ +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  devices_ms_ += renderer_.stats().devices_ms;
  vessels_ms_ += renderer_.stats().vessels_ms;
  writeLabels(data);
  char name[64];
  std::snprintf(name, sizeof(name), "/frame_%05ld.png", frames_);
  ++frames_;
  return writePng(options_.out + name, frame.width, frame.height, gray, why);
}

void XrayRecorder::writeLabels(const SimData& data) {
  const XrayCamera& c = renderer_.camera();
  for (size_t d = 0; d < data.devices.size(); ++d) {
    const Vec3 tip = c.project(data.devices[d].position.back());
    const std::string vessel = model_.atlas && d < data.tips.size() && data.tips[d].vessel >= 0
                                   ? model_.atlas->vessels()[data.tips[d].vessel].name
                                   : "";
    char line[256];
    std::snprintf(line, sizeof(line), "%ld,%.6f,%s,%.3f,%.3f,%.6f,%s\n", frames_, data.time,
                  model_.devices[d].name.c_str(), tip.x(), tip.y(), tip.z(), vessel.c_str());
    labels_ << line;
  }
  labels_.flush();
}

std::string XrayRecorder::summary() const {
  char line[256];
  const XrayCamera& c = renderer_.camera();
  std::snprintf(line, sizeof(line),
                "%ld frames of %dx%d px at %.3g frames/s: %.3g ms per frame on average "
                "(devices %.3g ms); vessels traced in %.3g ms (%ld field evaluations)",
                frames_, c.width, c.height, renderer_.spec().frame_rate,
                frames_ ? render_ms_ / frames_ : 0.0, frames_ ? devices_ms_ / frames_ : 0.0,
                renderer_.stats().vessels_ms, renderer_.stats().vessel_evaluations);
  return line;
}

}  // namespace evsim
