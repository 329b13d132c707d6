// The `xray:` section of a scene file, and the ranges of an X-ray system.
#include <cmath>
#include <string>

#include "scene_sections.h"

namespace evsim {

namespace {

std::string outside(const char* what, double v, const char* range) {
  return std::string(what) + " must lie in " + range + ", got " + std::to_string(v);
}

}  // namespace

std::string validateCArm(const CArmSpec& c) {
  if (!(std::abs(c.lao) <= M_PI / 2 + 1e-12))
    return outside("lao_deg", c.lao * 180 / M_PI, "[-90, 90] degrees");
  if (!(std::abs(c.cranial) <= M_PI / 3 + 1e-12))
    return outside("cranial_deg", c.cranial * 180 / M_PI, "[-60, 60] degrees");
  if (!(c.source_detector_distance >= 0.3 && c.source_detector_distance <= 2.0))
    return outside("source_detector_distance", c.source_detector_distance, "[0.3, 2] m");
  if (!(c.source_isocenter_distance >= 0.1 &&
        c.source_isocenter_distance <= 0.95 * c.source_detector_distance))
    return outside("source_isocenter_distance", c.source_isocenter_distance,
                   "[0.1 m, 0.95 source_detector_distance] (the patient lies between the "
                   "source and the detector)");
  if (!(c.detector_size >= 0.01 && c.detector_size <= 0.6))
    return outside("detector_size", c.detector_size, "[0.01, 0.6] m");
  if (!(c.pixels >= 8 && c.pixels <= 4096)) return outside("pixels", c.pixels, "[8, 4096]");
  if (!c.isocenter.allFinite()) return "isocenter must be finite";
  if (!(c.left.norm() > 0.0 && c.anterior.norm() > 0.0) ||
      std::abs(c.left.normalized().dot(c.anterior.normalized())) > 1e-6)
    return "left and anterior must be perpendicular, nonzero vectors";
  return "";
}

std::string validateXray(const XraySpec& x) {
  const std::string arm = validateCArm(x.c_arm);
  if (!arm.empty()) return arm;
  if (!(x.energy_kev >= 35.0 && x.energy_kev <= 120.0))
    return outside("energy_kev", x.energy_kev, "[35, 120] keV (diagnostic beams)");
  if (!(x.frame_rate >= 0.5 && x.frame_rate <= 60.0))
    return outside("frame_rate", x.frame_rate, "[0.5, 60] 1/s");
  if (!(x.iodine_concentration >= 0.0 && x.iodine_concentration <= 400.0))
    return outside("iodine_concentration", x.iodine_concentration, "[0, 400] kg/m^3 (mg/mL)");
  if (!(x.contrast_washout > 0.0 && x.contrast_washout <= 60.0))
    return outside("contrast_washout", x.contrast_washout, "(0, 60] s");
  if (!(x.body_width >= 0.0 && x.body_width <= 1.0 && x.body_depth >= 0.0 && x.body_depth <= 1.0))
    return "body_width and body_depth must lie in [0, 1] m";
  if (!(x.photons >= 0.0 && x.photons <= 1e9))
    return outside("photons", x.photons, "[0, 1e9] (0: no noise)");
  if (!(x.blur >= 0.0 && x.blur <= 20.0)) return outside("blur", x.blur, "[0, 20] px");
  const SpineSpec& sp = x.spine;
  if (sp.present &&
      (!sp.center.allFinite() || !(sp.radius > 0.0 && sp.radius <= 0.1) ||
       !(sp.vertebra > 0.0 && sp.vertebra <= 0.1) || !(sp.disc >= 0.0 && sp.disc <= 0.05) ||
       !(sp.bone_fraction > 0.0 && sp.bone_fraction <= 1.0)))
    return "spine: radius and vertebra must lie in (0, 0.1] m, disc in [0, 0.05] m, "
           "bone_fraction in (0, 1]";
  if (!(x.supersampling >= 1 && x.supersampling <= 8))
    return outside("supersampling", x.supersampling, "[1, 8]");
  return "";
}

XraySpec readXray(const YamlReader& r, const YAML::Node& n) {
  if (!n.IsMap()) r.fail(n, "xray", "must be a map (the C-arm, the beam, the contrast)");
  r.keys(n, "xray",
         {"lao_deg",
          "cranial_deg",
          "source_detector_distance",
          "source_isocenter_distance",
          "detector_size",
          "pixels",
          "isocenter",
          "left",
          "anterior",
          "energy_kev",
          "frame_rate",
          "iodine_concentration",
          "contrast_washout",
          "body_width",
          "body_depth",
          "photons",
          "blur",
          "seed",
          "supersampling",
          "spine"});
  XraySpec x;
  x.present = true;
  CArmSpec& c = x.c_arm;
  c.lao = r.number(n, "lao_deg", "xray.", 0.0) * M_PI / 180.0;
  c.cranial = r.number(n, "cranial_deg", "xray.", 0.0) * M_PI / 180.0;
  c.source_detector_distance =
      r.number(n, "source_detector_distance", "xray.", c.source_detector_distance);
  c.source_isocenter_distance =
      r.number(n, "source_isocenter_distance", "xray.", c.source_isocenter_distance);
  c.detector_size = r.number(n, "detector_size", "xray.", c.detector_size);
  if (n["pixels"]) c.pixels = r.integer(n["pixels"], "xray.pixels");
  if (n["isocenter"]) {
    c.isocenter = r.vector3(n["isocenter"], "xray.isocenter");
    c.isocenter_given = true;
  }
  if (n["left"]) c.left = r.vector3(n["left"], "xray.left");
  if (n["anterior"]) c.anterior = r.vector3(n["anterior"], "xray.anterior");
  x.energy_kev = r.number(n, "energy_kev", "xray.", x.energy_kev);
  x.frame_rate = r.number(n, "frame_rate", "xray.", x.frame_rate);
  x.iodine_concentration = r.number(n, "iodine_concentration", "xray.", x.iodine_concentration);
  x.contrast_washout = r.number(n, "contrast_washout", "xray.", x.contrast_washout);
  x.body_width = r.number(n, "body_width", "xray.", x.body_width);
  x.body_depth = r.number(n, "body_depth", "xray.", x.body_depth);
  x.photons = r.number(n, "photons", "xray.", x.photons);
  x.blur = r.number(n, "blur", "xray.", x.blur);
  if (n["seed"]) {
    const int seed = r.integer(n["seed"], "xray.seed");
    if (seed < 0) r.fail(n["seed"], "xray.seed", "must not be negative");
    x.seed = static_cast<unsigned>(seed);
  }
  if (n["supersampling"]) x.supersampling = r.integer(n["supersampling"], "xray.supersampling");
  if (n["spine"]) {
    const YAML::Node sp = n["spine"];
    if (!sp.IsMap()) r.fail(sp, "xray.spine", "must be a map {center, radius, ...}");
    r.keys(sp, "xray.spine", {"center", "radius", "vertebra", "disc", "bone_fraction"});
    x.spine.present = true;
    x.spine.center = r.vector3(r.required(sp, "center", "xray.spine.center"), "xray.spine.center");
    x.spine.radius = r.number(sp, "radius", "xray.spine.", x.spine.radius);
    x.spine.vertebra = r.number(sp, "vertebra", "xray.spine.", x.spine.vertebra);
    x.spine.disc = r.number(sp, "disc", "xray.spine.", x.spine.disc);
    x.spine.bone_fraction = r.number(sp, "bone_fraction", "xray.spine.", x.spine.bone_fraction);
  }
  const std::string why = validateXray(x);
  if (!why.empty()) r.fail(n, "xray", why);
  return x;
}

}  // namespace evsim
