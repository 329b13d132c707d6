// A flexible device (guidewire, catheter, coil) as a chain of beam elements:
// its description, and the immutable model built from it. Declared and
// documented in endovascular_sim/mechanics/device_model.h.
#include "endovascular_sim/mechanics/device_model.h"

#include <cmath>
#include <stdexcept>

#include "endovascular_sim/mechanics/so3.h"

namespace evsim {

namespace {

/// The element joining the detaching section to the one before it.
int detachElement(const DeviceSpec& spec) {
  int before = 0;  // elements before the detaching section
  size_t k = 0;
  for (; k < spec.sections.size() && spec.sections[k].name != spec.detach_section; ++k)
    before += spec.sections[k].elements;
  if (k == spec.sections.size() || k == 0)
    throw std::invalid_argument("detach_section '" + spec.detach_section +
                                "' must name a section after the first");
  return before - 1;
}

/// Checks the sections and copies their names and friction data into m;
/// returns their element count.
int readSections(const DeviceSpec& spec, DeviceModel* m) {
  int num_elements = 0;
  for (const auto& sec : spec.sections) {
    if (sec.elements < 1 || !(sec.length > 0.0))
      throw std::invalid_argument("section " + sec.name + " has no length or no elements");
    num_elements += sec.elements;
    m->section_names.push_back(sec.name);
    if (!(sec.friction >= 0.0))
      throw std::invalid_argument("section " + sec.name + " has a negative friction coefficient");
    m->section_friction.push_back(sec.friction);
    if (!(sec.lumen_friction >= 0.0))
      throw std::invalid_argument("section " + sec.name +
                                  " has a negative lumen friction coefficient");
    m->section_lumen_radius.push_back(sec.section.inner_radius);
    m->section_lumen_friction.push_back(sec.lumen_friction);
    m->section_xray_material.push_back(
        sec.xray_material >= 0 ? sec.xray_material : findXrayMaterial(kDefaultXrayMaterial));
    if (!(sec.xray_fill > 0.0 && sec.xray_fill <= 1.0))
      throw std::invalid_argument("section " + sec.name + " has an xray_fill outside (0, 1]");
    m->section_xray_fill.push_back(sec.xray_fill);
  }
  return num_elements;
}

/// The markers' bands in the device's material coordinate.
std::vector<XrayMarker> placeMarkers(const DeviceSpec& spec) {
  std::vector<XrayMarker> bands;
  for (const XrayMarkerSpec& mk : spec.markers) {
    if (mk.section < 0 || mk.section >= static_cast<int>(spec.sections.size()))
      throw std::invalid_argument("a marker names no section of the device");
    double start = 0.0;
    for (int k = 0; k < mk.section; ++k) start += spec.sections[k].length;
    const double length = spec.sections[mk.section].length;
    if (!(mk.length > 0.0) || mk.position < 0.0 || mk.position + mk.length > length * (1 + 1e-12))
      throw std::invalid_argument("a marker on section " + spec.sections[mk.section].name +
                                  " lies beyond it");
    bands.push_back({start + mk.position, start + mk.position + mk.length, mk.material});
  }
  return bands;
}

}  // namespace

DeviceModel buildDeviceModel(const DeviceSpec& spec) {
  if (spec.sections.empty()) throw std::invalid_argument("device has no sections");
  DeviceModel m;
  m.name = spec.name;
  m.max_insertion_speed = spec.max_insertion_speed;
  m.max_rotation_speed = spec.max_rotation_speed;
  m.rayleigh_mass = spec.rayleigh_mass;
  m.rayleigh_stiffness = spec.rayleigh_stiffness;
  if (!spec.detach_section.empty()) m.detach_element = detachElement(spec);
  m.num_nodes = readSections(spec, &m) + 1;
  m.xray_markers = placeMarkers(spec);
  const int n = m.num_nodes;
  m.node_s.assign(n, 0.0);
  m.node_mass.assign(n, 0.0);
  m.node_inertia.assign(n, Vec3::Zero());
  m.node_radius.assign(n, 0.0);
  m.rest_position.assign(n, Vec3::Zero());
  m.rest_rotation.assign(n, Mat3::Identity());
  m.rest_twist.assign(n, 0.0);

  int e = 0;
  double s = 0.0;
  for (int k = 0; k < static_cast<int>(spec.sections.size()); ++k) {
    const DeviceSectionSpec& sec = spec.sections[k];
    const double le = sec.length / sec.elements;
    const double mass = sec.section.density * sec.section.area() * le;
    const double rho_i = sec.section.density * sec.section.secondMoment() * le;
    const Vec3 inertia(2.0 * rho_i, rho_i, rho_i);
    for (int j = 0; j < sec.elements; ++j, ++e) {
      // Exact constant-curvature curve: R(s) = R1 exp(s hat(kappa)), and
      // x(le) - x(0) = R1 Jl(kappa le) e_x le, with Jl(phi) = Jr(-phi).
      const Vec3 step = sec.rest_curvature * le;
      const Mat3& R1 = m.rest_rotation[e];
      m.rest_rotation[e + 1] = R1 * expSO3(step);
      m.rest_position[e + 1] = m.rest_position[e] + R1 * rightJacobian(-step) * Vec3::UnitX() * le;
      m.rest_twist[e + 1] = m.rest_twist[e] + sec.rest_curvature.x() * le;
      s += le;
      m.node_s[e + 1] = s;

      BeamElementRest rest;
      setBeamElementRestShape(m.rest_position[e], R1, m.rest_position[e + 1],
                              m.rest_rotation[e + 1], le, &rest);
      rest.stretch_shear_stiffness = sec.section.stretchShearStiffness();
      rest.bend_twist_stiffness = sec.section.bendTwistStiffness();
      m.elements.push_back(rest);
      m.element_section.push_back(k);

      for (int node : {e, e + 1}) {
        m.node_mass[node] += 0.5 * mass;
        m.node_inertia[node] += 0.5 * inertia;
        m.node_radius[node] = std::max(m.node_radius[node], sec.section.outer_radius);
      }
    }
  }
  m.length = s;
  return m;
}

DeviceSpec straightDeviceSpec(const std::string& name, const BeamSection& section, double length,
                              int elements) {
  DeviceSpec spec;
  spec.name = name;
  DeviceSectionSpec sec;
  sec.name = name;
  sec.section = section;
  sec.length = length;
  sec.elements = elements;
  spec.sections.push_back(sec);
  return spec;
}

}  // namespace evsim
