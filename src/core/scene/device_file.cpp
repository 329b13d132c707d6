// Device files: URDF (read with urdfdom) plus an endovascular_sim extension.
// Declared and documented in endovascular_sim/scene/device_file.h.
#include "endovascular_sim/scene/device_file.h"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "endovascular_sim/core/edit_distance.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/mechanics/radiopacity.h"

namespace evsim {
namespace {

/// Reads numbers from the attributes of one XML element, reporting errors
/// with the file, the element's line and the attribute's name.
class AttributeReader {
 public:
  AttributeReader(const std::string& file, const TiXmlElement* element, std::string prefix)
      : file_(file), element_(element), prefix_(std::move(prefix)) {}

  bool has(const char* name) const { return element_->Attribute(name) != nullptr; }

  std::vector<double> numbers(const char* name, size_t count) const {
    const char* text = element_->Attribute(name);
    if (!text) fail(name, "is missing");
    std::istringstream in(text);
    std::vector<double> values;
    std::string token;
    while (in >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0') fail(name, "'" + token + "' is not a number");
      if (!std::isfinite(v)) fail(name, "must be finite, got '" + token + "'");
      values.push_back(v);
    }
    if (values.size() != count)
      fail(name,
           "needs " + std::to_string(count) + " number(s), got " + std::to_string(values.size()));
    return values;
  }

  double number(const char* name) const { return numbers(name, 1)[0]; }
  double number(const char* name, double fallback) const {
    return has(name) ? number(name) : fallback;
  }
  double positive(const char* name) const {
    const double v = number(name);
    if (!(v > 0.0)) fail(name, "must be positive, got " + std::to_string(v));
    return v;
  }
  double positive(const char* name, double fallback) const {
    return has(name) ? positive(name) : fallback;
  }
  double nonNegative(const char* name, double fallback) const {
    const double v = number(name, fallback);
    if (v < 0.0) fail(name, "must not be negative, got " + std::to_string(v));
    return v;
  }

  /// A material of xrayMaterials() by name (index).
  int xrayMaterial(const char* name) const {
    const char* text = element_->Attribute(name);
    if (!text) fail(name, "is missing");
    const int index = findXrayMaterial(text);
    if (index >= 0) return index;
    std::vector<std::string> names;
    for (const XrayMaterial& m : xrayMaterials()) names.push_back(m.name);
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    const auto near = nearestNames(text, names, 1);
    fail(name, std::string("unknown material '") + text + "'" +
                   (near.empty() ? "" : " (did you mean '" + near[0] + "'?)") + "; known: " + list);
  }

  [[noreturn]] void fail(const std::string& name, const std::string& what) const {
    throw LoadError(file_, element_->Row(), prefix_ + name, what);
  }

 private:
  const std::string& file_;
  const TiXmlElement* element_;
  std::string prefix_;
};

const TiXmlElement* findLinkElement(const TiXmlElement* robot, const std::string& name) {
  for (auto* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link"))
    if (e->Attribute("name") && name == e->Attribute("name")) return e;
  return nullptr;
}

const TiXmlElement* findCylinder(const TiXmlElement* link) {
  for (const char* kind : {"collision", "visual"}) {
    const TiXmlElement* e = link->FirstChildElement(kind);
    if (e && e->FirstChildElement("geometry") &&
        e->FirstChildElement("geometry")->FirstChildElement("cylinder"))
      return e->FirstChildElement("geometry")->FirstChildElement("cylinder");
  }
  return nullptr;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the device file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

DeviceSectionSpec readSection(const std::string& path, const TiXmlElement* robot,
                              const TiXmlElement* ext, const std::string& link_name) {
  DeviceSectionSpec sec;
  sec.name = link_name;
  const TiXmlElement* link = findLinkElement(robot, link_name);
  const std::string where = "link[" + link_name + "]/";

  const TiXmlElement* cylinder = findCylinder(link);
  if (!cylinder)
    throw LoadError(path, link->Row(), where + "collision/geometry/cylinder",
                    "a section needs a cylinder geometry");
  AttributeReader cyl(path, cylinder, where + "cylinder/");
  sec.section.outer_radius = cyl.positive("radius");
  sec.length = cyl.positive("length");
  // The other geometry (a visual beside the collision) is checked too: a
  // negative or zero radius anywhere in the file is an error, not ignored.
  for (const char* kind : {"collision", "visual"}) {
    const TiXmlElement* e = link->FirstChildElement(kind);
    const TiXmlElement* g = e ? e->FirstChildElement("geometry") : nullptr;
    const TiXmlElement* other = g ? g->FirstChildElement("cylinder") : nullptr;
    if (!other || other == cylinder) continue;
    AttributeReader o(path, other, where + kind + "/geometry/cylinder/");
    o.positive("radius");
    o.positive("length");
  }

  const TiXmlElement* inertial = link->FirstChildElement("inertial");
  const TiXmlElement* mass = inertial ? inertial->FirstChildElement("mass") : nullptr;
  if (!mass) throw LoadError(path, link->Row(), where + "inertial/mass", "is missing");
  const double m = AttributeReader(path, mass, where + "inertial/mass/").positive("value");

  AttributeReader x(path, ext, "evsim_section[" + link_name + "]/");
  sec.section.young_modulus = x.positive("young_modulus");
  if (x.has("shear_modulus")) {
    sec.section.shear_modulus = x.positive("shear_modulus");
  } else {
    const double nu = x.number("poisson_ratio");
    if (!(nu > -1.0 && nu < 0.5)) x.fail("poisson_ratio", "must lie in (-1, 0.5)");
    sec.section.shear_modulus = sec.section.young_modulus / (2.0 * (1.0 + nu));
  }
  sec.section.inner_radius = x.nonNegative("inner_radius", 0.0);
  if (sec.section.inner_radius >= sec.section.outer_radius)
    x.fail("inner_radius", "must be smaller than the cylinder radius " +
                               std::to_string(sec.section.outer_radius) + " m");
  const double elements = x.positive("elements");
  if (elements != std::floor(elements) || elements > 100000)
    x.fail("elements", "must be a whole number of at most 100000");
  sec.elements = static_cast<int>(elements);
  if (x.has("rest_curvature")) {
    const auto k = x.numbers("rest_curvature", 3);
    sec.rest_curvature = Vec3(k[0], k[1], k[2]);
    if (sec.rest_curvature.norm() * sec.length / sec.elements >= M_PI / 2)
      x.fail("rest_curvature", "turns more than 90 degrees per element: add elements");
  }
  sec.friction = x.nonNegative("friction", 0.0);
  sec.lumen_friction = x.nonNegative("lumen_friction", 0.0);
  if (sec.lumen_friction > 0.0 && sec.section.inner_radius == 0.0)
    x.fail("lumen_friction", "a solid section (inner_radius 0) has no lumen");
  if (x.has("xray_material")) sec.xray_material = x.xrayMaterial("xray_material");
  sec.xray_fill = x.number("xray_fill", 1.0);
  if (!(sec.xray_fill > 0.0 && sec.xray_fill <= 1.0))
    x.fail("xray_fill",
           "must lie in (0, 1] (the fraction of the cross-section the material fills)");
  sec.section.density = m / (sec.section.area() * sec.length);
  return sec;
}

/// A radiopaque band: <evsim_marker link position length material/>.
XrayMarkerSpec readMarker(const std::string& path, const TiXmlElement* e, const DeviceSpec& spec) {
  AttributeReader x(path, e, "evsim_marker/");
  const char* link = e->Attribute("link");
  if (!link) x.fail("link", "is missing");
  XrayMarkerSpec marker;
  marker.section = -1;
  for (size_t k = 0; k < spec.sections.size(); ++k)
    if (spec.sections[k].name == link) marker.section = static_cast<int>(k);
  if (marker.section < 0) x.fail("link", std::string("no section named '") + link + "'");
  marker.position = x.nonNegative("position", 0.0);
  marker.length = x.positive("length");
  marker.material = x.xrayMaterial("material");
  const double section_length = spec.sections[marker.section].length;
  if (marker.position + marker.length > section_length * (1.0 + 1e-12))
    x.fail("position", "the band (position + length) ends beyond its link's " +
                           std::to_string(section_length) + " m");
  return marker;
}

}  // namespace

namespace {

/// Collects urdfdom's messages (warnings and errors).
struct UrdfMessages : console_bridge::OutputHandler {
  std::string text;
  void log(const std::string& message, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
    text += (text.empty() ? "" : "; ") + message;
  }
};

/// The URDF as urdfdom reads it. urdfdom reports through console_bridge:
/// its messages become the error's text instead of lines on stderr.
urdf::ModelInterfaceSharedPtr parseWithUrdfdom(const std::string& path, const std::string& text,
                                               const TiXmlElement* robot) {
  UrdfMessages messages;
  console_bridge::useOutputHandler(&messages);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  console_bridge::restorePreviousOutputHandler();
  if (!model)
    throw LoadError(path, robot->Row(), "robot",
                    "urdfdom rejected the URDF: " +
                        (messages.text.empty() ? std::string("(no reason given)") : messages.text));
  return model;
}

/// `<evsim_device>`: the drive's limits, Rayleigh damping, the detachable
/// section (after the sections are read).
void readDeviceElement(const std::string& path, const TiXmlElement* robot, DeviceSpec* spec) {
  const TiXmlElement* device = robot->FirstChildElement("evsim_device");
  if (!device) throw LoadError(path, robot->Row(), "evsim_device", "is missing");
  AttributeReader d(path, device, "evsim_device/");
  spec->max_insertion_speed = d.positive("max_insertion_speed");
  spec->max_rotation_speed = d.positive("max_rotation_speed");
  spec->rayleigh_mass = d.nonNegative("rayleigh_mass", 0.0);
  spec->rayleigh_stiffness = d.nonNegative("rayleigh_stiffness", 0.0);
  spec->drive_max_force = d.positive("drive_max_force", kDefaultDriveMaxForce);
  spec->drive_max_torque = d.positive("drive_max_torque", kDefaultDriveMaxTorque);
  const char* cut = device->Attribute("detach_section");
  if (!cut) return;
  spec->detach_section = cut;
  const auto& sections = spec->sections;
  if (sections.size() < 2 || sections.front().name == spec->detach_section ||
      std::none_of(sections.begin(), sections.end(),
                   [&](const DeviceSectionSpec& s) { return s.name == spec->detach_section; }))
    d.fail("detach_section", "'" + spec->detach_section +
                                 "' must name a link after the first (the part that detaches "
                                 "from the pusher)");
}

}  // namespace

DeviceSpec loadDeviceFile(const std::string& path) {
  const std::string text = readFile(path);
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  if (doc.Error())
    throw LoadError(path, doc.ErrorRow(), "", std::string("malformed XML: ") + doc.ErrorDesc());
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot")
    throw LoadError(path, robot ? robot->Row() : 0, "robot", "the root element must be <robot>");

  const urdf::ModelInterfaceSharedPtr urdf_model = parseWithUrdfdom(path, text, robot);
  DeviceSpec spec;
  spec.name = urdf_model->getName();

  // Extension elements by link name.
  std::map<std::string, const TiXmlElement*> sections;
  for (auto* e = robot->FirstChildElement("evsim_section"); e;
       e = e->NextSiblingElement("evsim_section")) {
    const char* link = e->Attribute("link");
    if (!link) throw LoadError(path, e->Row(), "evsim_section/link", "is missing");
    if (!urdf_model->getLink(link))
      throw LoadError(path, e->Row(), "evsim_section/link",
                      std::string("no link named '") + link + "'");
    if (!sections.emplace(link, e).second)
      throw LoadError(path, e->Row(), "evsim_section/link",
                      std::string("'") + link + "' appears twice");
  }

  // Walk the chain from the root (proximal) link.
  urdf::LinkConstSharedPtr link = urdf_model->getRoot();
  std::vector<LoadError> problems;  // of every section, then of every marker
  while (link) {
    const auto found = sections.find(link->name);
    if (found == sections.end())
      throw LoadError(path, findLinkElement(robot, link->name)->Row(),
                      "evsim_section[" + link->name + "]",
                      "every link needs an <evsim_section link=\"" + link->name + "\"/>");
    try {
      spec.sections.push_back(readSection(path, robot, found->second, link->name));
    } catch (const LoadError& e) {
      problems.push_back(e);
    }
    if (link->child_links.size() > 1)
      throw LoadError(path, findLinkElement(robot, link->name)->Row(), "link[" + link->name + "]",
                      "a device is a chain: this link has several children");
    link = link->child_links.empty() ? nullptr : link->child_links[0];
  }
  throwLoadErrors(problems);

  for (const auto& [name, joint] : urdf_model->joints_)
    if (joint->type != urdf::Joint::FIXED)
      throw LoadError(path, robot->Row(), "joint[" + name + "]",
                      "is not fixed: a device's sections are joined by fixed joints (its bending "
                      "is the beams')");
  long elements = 0;
  for (const DeviceSectionSpec& sec : spec.sections) elements += sec.elements;
  if (elements > 100000)
    throw LoadError(path, robot->Row(), "evsim_section/elements",
                    "the sections hold " + std::to_string(elements) +
                        " elements, more than the limit of 100000 a device");

  for (auto* e = robot->FirstChildElement("evsim_marker"); e;
       e = e->NextSiblingElement("evsim_marker")) {
    try {
      spec.markers.push_back(readMarker(path, e, spec));
    } catch (const LoadError& error) {
      problems.push_back(error);
    }
  }
  throwLoadErrors(problems);

  readDeviceElement(path, robot, &spec);
  return spec;
}

}  // namespace evsim
