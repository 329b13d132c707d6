// Virtual fluoroscopy. Declared and documented in
// endovascular_sim/imaging/xray_renderer.h.
#include "endovascular_sim/imaging/xray_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "endovascular_sim/imaging/ray_geometry.h"

namespace evsim {

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

/// The sub-ray offsets of a pixel: s x s points at the centres of its cells.
double subOffset(int j, int s) { return (j + 0.5) / s - 0.5; }

}  // namespace

XrayRenderer::XrayRenderer(const SceneModel& model, const XraySpec& spec)
    : model_(&model), spec_(spec), mu_(attenuationAt(spec.energy_kev)) {
  const std::string why = validateXray(spec);
  if (!why.empty()) throw std::invalid_argument("xray: " + why);
  if (model.vessels) default_isocenter_ = model.vessels->bounds().center();
  contrast_ = ContrastAgent(model.centerline);
  camera_ = cameraOf(spec_.c_arm, default_isocenter_);
  prepareCamera();
}

void XrayRenderer::setCArm(const CArmSpec& c_arm) {
  const std::string why = validateCArm(c_arm);
  if (!why.empty()) throw std::invalid_argument("c-arm: " + why);
  spec_.c_arm = c_arm;
  camera_ = cameraOf(spec_.c_arm, default_isocenter_);
  prepareCamera();
}

void XrayRenderer::setDetector(double frame_rate, double photons, double blur) {
  XraySpec spec = spec_;
  spec.frame_rate = frame_rate;
  spec.photons = photons;
  spec.blur = blur;
  const std::string why = validateXray(spec);
  if (!why.empty()) throw std::invalid_argument("detector: " + why);
  spec_ = spec;
}

void XrayRenderer::prepareCamera() {
  const auto start = std::chrono::steady_clock::now();
  const int w = camera_.width, h = camera_.height, s = 1;  // smooth at a pixel's scale
  const CArmSpec& c = spec_.c_arm;
  const Vec3 left = c.left.normalized();
  const Vec3 superior = left.cross(c.anterior.normalized());
  body_.assign(static_cast<size_t>(w) * h, 0.0f);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      double chord = 0.0;
      for (int j = 0; j < s * s; ++j) {
        const Vec3 d = camera_.ray(u + subOffset(j % s, s), v + subOffset(j / s, s));
        chord += rayInEllipticCylinder(camera_.source, d, camera_.isocenter, superior, left,
                                       0.5 * spec_.body_width, 0.5 * spec_.body_depth)
                     .length();
      }
      body_[static_cast<size_t>(v) * w + u] = static_cast<float>(mu_.soft_tissue * chord / (s * s));
    }
  bones_.clear();
  if (spec_.spine.present) {
    // Vertebral bodies stacked along the superior axis over the field of
    // view: bone replacing soft tissue in `bone_fraction` of their volume.
    const SpineSpec& sp = spec_.spine;
    const double mu = sp.bone_fraction * (mu_.bone - mu_.soft_tissue);
    const double pitch = sp.vertebra + sp.disc;
    const double reach = 0.6;  // [m] along the axis either side of `center`
    bones_.assign(static_cast<size_t>(w) * h, 0.0f);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const Vec3 d = camera_.ray(u, v);
        const RayInterval in =
            rayInCylinder(camera_.source, d, sp.center, superior, sp.radius, -reach, reach);
        if (in.empty()) continue;
        // The column's stretch of this ray, cut into bodies and discs.
        double s0 = (camera_.source + in.t0 * d - sp.center).dot(superior);
        double s1 = (camera_.source + in.t1 * d - sp.center).dot(superior);
        if (s0 > s1) std::swap(s0, s1);
        const double per_s = in.length() / std::max(s1 - s0, 1e-12);
        double bone = 0.0;
        for (double k = std::floor(s0 / pitch); k * pitch < s1; k += 1.0) {
          const double lo = std::max(s0, k * pitch), hi = std::min(s1, k * pitch + sp.vertebra);
          if (hi > lo) bone += hi - lo;
        }
        // A ray along the axis (s0 == s1) lies in one body or disc.
        if (s1 - s0 < 1e-12) {
          const double f = s0 / pitch - std::floor(s0 / pitch);
          bone = f * pitch < sp.vertebra ? in.length() : 0.0;
          bones_[static_cast<size_t>(v) * w + u] = static_cast<float>(mu * bone);
          continue;
        }
        bones_[static_cast<size_t>(v) * w + u] = static_cast<float>(mu * bone * per_s);
      }
  }
  vessels_ = VesselProjection();
  vessels_traced_ = false;
  stats_.body_ms = msSince(start);
}

int XrayRenderer::injectContrast(const Vec3& at, double time, double duration) {
  if (!(duration > 0.0 && duration <= 60.0))
    throw std::invalid_argument("contrast: the injection's duration must lie in (0, 60] s");
  return contrast_.inject(at, time, duration, spec_.iodine_concentration, spec_.contrast_washout);
}

std::vector<DevicePose> XrayRenderer::posesOf(const SimData& data) {
  std::vector<DevicePose> poses;
  for (const DeviceState& d : data.devices) poses.push_back({d.position, d.cut_element});
  return poses;
}

void XrayRenderer::addDevice(const DeviceModel& m, const DevicePose& pose,
                             std::vector<float>* image) const {
  const int w = camera_.width, h = camera_.height, s = spec_.supersampling;
  const float weight = 1.0f / (s * s);
  for (int e = 0; e + 1 < static_cast<int>(pose.nodes.size()); ++e) {
    if (e == pose.cut_element) continue;
    const int sec = m.element_section[e];
    const Vec3& a = pose.nodes[e];
    const Vec3 ab = pose.nodes[e + 1] - a;
    const double length = ab.norm();
    if (!(length > 0.0)) continue;
    const Vec3 axis = ab / length;
    const double r = 0.5 * (m.node_radius[e] + m.node_radius[e + 1]);
    const double r_in = m.section_lumen_radius[sec];
    const double mu = mu_.device_material[m.section_xray_material[sec]] * m.section_xray_fill[sec];
    // Marker bands over this element, as slabs of its axis [m].
    struct Band {
      double s0, s1, extra_mu;
    };
    std::vector<Band> bands;
    const double se = m.node_s[e], se1 = m.node_s[e + 1];
    for (const XrayMarker& mk : m.xray_markers) {
      const double lo = std::max(mk.s_begin, se), hi = std::min(mk.s_end, se1);
      if (hi > lo)
        bands.push_back({(lo - se) / (se1 - se) * length, (hi - se) / (se1 - se) * length,
                         mu_.device_material[mk.material] - mu});
    }
    const Vec3 pa = camera_.project(a), pb = camera_.project(pose.nodes[e + 1]);
    const double near = std::min(pa.z(), pb.z()) - r;
    if (!(near > 0.0)) continue;
    const double grow = r * camera_.fx / near + 1.0;
    const int u0 = std::max(0, static_cast<int>(std::floor(std::min(pa.x(), pb.x()) - grow)));
    const int u1 = std::min(w - 1, static_cast<int>(std::ceil(std::max(pa.x(), pb.x()) + grow)));
    const int v0 = std::max(0, static_cast<int>(std::floor(std::min(pa.y(), pb.y()) - grow)));
    const int v1 = std::min(h - 1, static_cast<int>(std::ceil(std::max(pa.y(), pb.y()) + grow)));
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        double sum = 0.0;
        for (int j = 0; j < s * s; ++j) {
          const Vec3 d = camera_.ray(u + subOffset(j % s, s), v + subOffset(j / s, s));
          auto chord = [&](double s0, double s1) {
            double c = rayInCylinder(camera_.source, d, a, axis, r, s0, s1).length();
            if (r_in > 0.0) c -= rayInCylinder(camera_.source, d, a, axis, r_in, s0, s1).length();
            return c;
          };
          const double whole = chord(0.0, length);
          if (whole <= 0.0) continue;
          sum += mu * whole;
          for (const Band& b : bands) sum += b.extra_mu * chord(b.s0, b.s1);
        }
        if (sum > 0.0) (*image)[static_cast<size_t>(v) * w + u] += weight * static_cast<float>(sum);
      }
  }
}

void XrayRenderer::render(const std::vector<DevicePose>& devices, double time, XrayFrame* frame) {
  const int w = camera_.width, h = camera_.height;
  frame->width = w;
  frame->height = h;
  frame->time = time;
  frame->attenuation = body_;
  for (size_t p = 0; p < bones_.size(); ++p) frame->attenuation[p] += bones_[p];
  frame->contrast.assign(static_cast<size_t>(w) * h, 0.0f);

  if (model_->vessels && model_->centerline && contrast_.active(time)) {
    std::vector<double> mu(model_->centerline->numPoints(), 0.0);
    for (int k = 0; k < static_cast<int>(mu.size()); ++k)
      mu[k] = contrast_.concentration(k, time) * mu_.iodine_mass;
    // Static vessels: the whole tree once per C-arm pose. Moving vessels:
    // each frame, the segments that hold contrast, where the motion has
    // carried them.
    const bool moves = model_->vessels->moves();
    if (!vessels_traced_ || moves) {
      const auto start = std::chrono::steady_clock::now();
      std::vector<char> filled;
      if (moves)
        for (const double m : mu) filled.push_back(m > 0.0);
      vessels_.build(*model_->vessels, *model_->centerline, model_->aneurysms, camera_,
                     1,  // the lumen is wide and smooth at a pixel's scale
                     moves ? model_->vessels->motionAt(time) : MotionSnapshot{}, 0.0,
                     moves ? &filled : nullptr);
      vessels_traced_ = true;
      stats_.vessels_ms = msSince(start);
      stats_.vessel_evaluations = vessels_.fieldEvaluations();
    }
    const auto start = std::chrono::steady_clock::now();
    vessels_.addAttenuation(mu, &frame->contrast);
    for (size_t p = 0; p < frame->attenuation.size(); ++p)
      frame->attenuation[p] += frame->contrast[p];
    stats_.compose_ms = msSince(start);
  }

  const auto start = std::chrono::steady_clock::now();
  for (size_t d = 0; d < devices.size() && d < model_->devices.size(); ++d)
    addDevice(model_->devices[d], devices[d], &frame->attenuation);
  stats_.devices_ms = msSince(start);
}

}  // namespace evsim
