// Scene files (YAML): time step, effects, devices and where they enter, and an
// optional script of commands. Declared and documented in
// endovascular_sim/scene/scene_file.h.
#include "endovascular_sim/scene/scene_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/scene/centerline_vtk.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_schema.h"
#include "endovascular_sim/scene/yaml_reader.h"
#include "scene_sections.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

constexpr double kMinTimeStep = 1e-6;       // [s] a million steps per simulated second
constexpr double kMaxTimeStep = 0.04;       // [s] one step per 25 Hz frame
constexpr double kMaxGravity = 1000.0;      // [m/s^2] 100 g
constexpr double kMaxDuration = 3600.0;     // [s] a scripted procedure
constexpr double kMinElementLength = 1e-5;  // [m] max_element_length's floor
constexpr double kMaxDeviceElements = 1e5;  // per device, after refinement

/// `drive: {max_force: N | unlimited, max_torque: N m | unlimited,
/// valve_friction: N, valve_torque: N m}` over the device file's limits
/// (`drive`): each limit positive, `unlimited` for a kinematic drive, the
/// device file's when omitted; the valve's grip not negative, 0 when omitted.
DriveSpec readDrive(const YamlReader& r, const YAML::Node& n, const std::string& key,
                    DriveSpec drive) {
  r.keys(n, key, {"max_force", "max_torque", "valve_friction", "valve_torque"});
  for (const char* name : {"max_force", "max_torque"}) {
    if (!n[name]) continue;
    double& limit = name[4] == 'f' ? drive.max_force : drive.max_torque;
    if (n[name].IsScalar() && n[name].Scalar() == "unlimited") {
      limit = std::numeric_limits<double>::infinity();
      continue;
    }
    const double v = r.number(n[name], key + "." + name);
    if (!(v > 0.0) || !std::isfinite(v))
      r.fail(n[name], key + "." + name,
             std::string("must be a positive ") + (name[4] == 'f' ? "force [N]" : "torque [N m]") +
                 " or unlimited (a kinematic drive)");
    limit = v;
  }
  drive.valve_friction = r.number(n, "valve_friction", key + ".", 0.0);
  drive.valve_torque = r.number(n, "valve_torque", key + ".", 0.0);
  if (!(drive.valve_friction >= 0.0 && drive.valve_friction <= 100.0))
    r.fail(n["valve_friction"], key + ".valve_friction", "must lie in [0, 100] N");
  if (!(drive.valve_torque >= 0.0 && drive.valve_torque <= 1.0))
    r.fail(n["valve_torque"], key + ".valve_torque", "must lie in [0, 1] N m");
  return drive;
}

/// A device of another length than its file's, as catheters and wires come
/// in several: the first (proximal) section takes the difference, at the
/// file's element length or finer.
void resizeShaft(const YamlReader& r, const YAML::Node& n, const std::string& key,
                 DeviceSpec* device) {
  const double length = r.number(n, key);
  double distal = 0.0;
  for (size_t i = 1; i < device->sections.size(); ++i) distal += device->sections[i].length;
  DeviceSectionSpec& shaft = device->sections.front();
  if (!(length <= 10.0) || !(length >= distal + 1e-3)) {
    std::ostringstream why;
    why << "must lie in [" << (distal + 1e-3) << ", 10] m: its first section '" << shaft.name
        << "' takes the change, and the sections beyond it are " << distal << " m long";
    r.fail(n, key, why.str());
  }
  const double element = shaft.length / shaft.elements;
  shaft.length = length - distal;
  shaft.elements = std::max(1, static_cast<int>(std::ceil(shaft.length / element - 1e-6)));
  if (shaft.elements > kMaxDeviceElements)
    r.fail(n, key,
           "makes its first section " + std::to_string(shaft.elements) +
               " elements long, more than the limit of 100000");
}

DevicePlacementSpec readDevice(const YamlReader& r, const YAML::Node& n, int index,
                               const fs::path& scene_dir) {
  const std::string p = "devices[" + std::to_string(index) + "].";
  r.keys(n, p.substr(0, p.size() - 1),
         {"file", "name", "inside", "access_point", "insertion_direction", "up", "inserted_length",
          "rotation", "length", "max_element_length", "drive"});
  DevicePlacementSpec d;
  const fs::path file = r.text(r.required(n, "file", p + "file"), p + "file");
  d.file = (file.is_absolute() ? file : scene_dir / file).lexically_normal().string();
  if (!fs::exists(d.file)) r.fail(n["file"], p + "file", "no device file " + d.file);
  d.device = loadDeviceFile(d.file);
  if (n["name"]) d.device.name = r.text(n["name"], p + "name");
  if (n["inside"]) {  // enters through the outer device: its introducer (resolved by the caller)
    d.inside = r.text(n["inside"], p + "inside");
    for (const char* key : {"access_point", "insertion_direction", "up"})
      if (n[key])
        r.fail(n[key], p + key,
               "a device inside another enters through that device's introducer: remove it");
  } else if (n["access_point"] && n["access_point"].IsScalar()) {
    if (r.text(n["access_point"], p + "access_point") != "inlet")
      r.fail(n["access_point"], p + "access_point", "must be [x, y, z] or inlet");
    for (const char* key : {"insertion_direction", "up"})
      if (n[key])
        r.fail(n[key], p + key, "follows the centreline at its inlet (access_point: inlet)");
    d.at_inlet = true;
    d.access_point_line = n["access_point"].Mark().line + 1;
  } else {
    d.introducer.access_point =
        r.vector3(r.required(n, "access_point", p + "access_point"), p + "access_point");
    d.access_point_line = n["access_point"].Mark().line + 1;
    const Vec3 dir = r.vector3(r.required(n, "insertion_direction", p + "insertion_direction"),
                               p + "insertion_direction");
    if (dir.norm() < 1e-9) r.fail(n["insertion_direction"], p + "insertion_direction", "is zero");
    const Vec3 up = n["up"] ? r.vector3(n["up"], p + "up") : Vec3(0.0, 0.0, 1.0);
    d.introducer.frame = introducerFrame(dir, up);
  }
  if (n["length"]) resizeShaft(r, n["length"], p + "length", &d.device);
  if (n["max_element_length"]) {  // a finer discretisation than the device file's
    const double h = r.number(n["max_element_length"], p + "max_element_length");
    if (!(h >= kMinElementLength))
      r.fail(n["max_element_length"], p + "max_element_length",
             "must be at least 1e-5 m (10 um): finer elements are far below what a device's "
             "bending needs, and their count would not fit in memory");
    double total = 0.0;
    for (const DeviceSectionSpec& sec : d.device.sections)
      total += std::max<double>(sec.elements, std::ceil(sec.length / h));
    if (total > kMaxDeviceElements)
      r.fail(n["max_element_length"], p + "max_element_length",
             "refines the device to " + std::to_string(static_cast<long>(total)) +
                 " elements, more than the limit of 100000 (kMaxDeviceElements in "
                 "scene_file.cpp): use a longer length");
    for (DeviceSectionSpec& sec : d.device.sections)
      sec.elements = std::max(sec.elements, static_cast<int>(std::ceil(sec.length / h - 1e-9)));
    d.max_element_length = h;
    d.max_element_length_line = n["max_element_length"].Mark().line + 1;
  }
  const DeviceModel model = buildDeviceModel(d.device);
  d.inserted_length = r.number(n, "inserted_length", p, 0.0);
  if (n["inserted_length"]) d.inserted_length_line = n["inserted_length"].Mark().line + 1;
  // The device's length is a sum of its sections': a full insertion written
  // as the nominal length may exceed it by round-off.
  if (d.inserted_length < 0.0 || d.inserted_length > model.length * (1.0 + kLengthTolerance))
    r.fail(n["inserted_length"], p + "inserted_length",
           "must lie in [0, " + std::to_string(model.length) + "] m (the device's length)");
  d.inserted_length = std::min(d.inserted_length, model.length);
  d.rotation = r.number(n, "rotation", p, 0.0);
  d.drive.max_force = d.device.drive_max_force;
  d.drive.max_torque = d.device.drive_max_torque;
  if (n["drive"]) d.drive = readDrive(r, n["drive"], p + "drive", d.drive);
  return d;
}

/// The `contact:` section, key by key from the contact options' table
/// (contact/contact_options.h); the schema check has already refused
/// values of the wrong type or out of range.
ContactOptions readContact(const YamlReader& r, const YAML::Node& n) {
  ContactOptions o;
  if (n.IsMap())
    for (const auto& entry : n)
      if (entry.first.IsScalar())
        if (const RetiredKey* retired = findRetiredKey("contact." + entry.first.Scalar()))
          r.fail(entry.first, retired->path, retired->why);
  std::vector<std::string> keys;
  for (const ContactOptionField& f : contactOptionFields()) keys.push_back(f.key);
  r.keys(n, "contact", keys);
  for (const ContactOptionField& f : contactOptionFields()) {
    const YAML::Node v = n[f.key];
    if (!v) continue;
    const std::string path = "contact." + f.key;
    switch (f.type) {
      case OptionType::kNumber:
        f.set(&o, r.number(v, path));
        break;
      case OptionType::kInteger: {
        const double x = r.number(v, path);
        if (x != std::floor(x) || std::abs(x) > 1e9) r.fail(v, path, "must be a whole number");
        f.set(&o, x);
        break;
      }
      case OptionType::kBool: {
        const std::string t = r.text(v, path);
        if (t != "true" && t != "false") r.fail(v, path, "must be true or false");
        f.set(&o, t == "true" ? 1.0 : 0.0);
        break;
      }
      case OptionType::kChoice: {
        const std::string t = r.text(v, path);
        const auto c = std::find(f.choices.begin(), f.choices.end(), t);
        if (c == f.choices.end()) r.fail(v, path, "must be " + contactOptionRange(f));
        f.set(&o, static_cast<double>(c - f.choices.begin()));
        break;
      }
    }
  }
  const std::string why = validateContactOptions(o);
  if (!why.empty()) r.fail(n, "contact", why);
  return o;
}

/// Effect 'coaxial': the outer device of devices[i] ("inside: NAME") is
/// listed before it, and every section of the inner device fits the outer
/// device's narrowest lumen.
void resolveOuterDevice(const YamlReader& r, const YAML::Node& n, int i, SceneSpec* scene) {
  DevicePlacementSpec& inner = scene->devices[i];
  const std::string p = "devices[" + std::to_string(i) + "].inside";
  for (int j = 0; j < i; ++j)
    if (scene->devices[j].device.name == inner.inside) inner.outer = j;
  if (inner.outer < 0) {
    std::string names;
    for (int j = 0; j < i; ++j)
      names += (names.empty() ? "" : ", ") + scene->devices[j].device.name;
    r.fail(n["inside"], p,
           "unknown device '" + inner.inside + "' (the outer device must be listed before; " +
               (names.empty() ? std::string("none is") : "listed before: " + names) + ")");
  }
  const DevicePlacementSpec& outer = scene->devices[inner.outer];
  inner.introducer = outer.introducer;
  double lumen = INFINITY;
  std::string narrowest;
  for (const auto& sec : outer.device.sections)
    if (sec.section.inner_radius < lumen) {
      lumen = sec.section.inner_radius;
      narrowest = sec.name;
    }
  for (const auto& sec : inner.device.sections)
    if (sec.section.outer_radius >= lumen) {
      std::ostringstream why;
      why << "section '" << sec.name << "' of device '" << inner.device.name << "' (radius "
          << sec.section.outer_radius * 1e3 << " mm) is wider than the lumen of '"
          << outer.device.name << "' (radius " << lumen * 1e3 << " mm in section '" << narrowest
          << "')";
      r.fail(n["inside"], p, why.str());
    }
}

ScriptedCommand readCommand(const YamlReader& r, const YAML::Node& n, int index,
                            const SceneSpec& scene) {
  const std::string p = "script[" + std::to_string(index) + "].";
  r.keys(n, p.substr(0, p.size() - 1), {"time", "device", "mode", "insertion", "rotation"});
  ScriptedCommand c;
  c.time = r.number(r.required(n, "time", p + "time"), p + "time");
  if (c.time < 0.0) r.fail(n["time"], p + "time", "must not be negative");
  const std::string name = r.text(r.required(n, "device", p + "device"), p + "device");
  c.device = -1;
  for (size_t i = 0; i < scene.devices.size(); ++i)
    if (scene.devices[i].device.name == name) c.device = static_cast<int>(i);
  if (c.device < 0) r.fail(n["device"], p + "device", "unknown device '" + name + "'");
  const std::string mode = n["mode"] ? r.text(n["mode"], p + "mode") : "velocity";
  if (mode == "velocity")
    c.command.mode = DriveCommand::Mode::kVelocity;
  else if (mode == "position")
    c.command.mode = DriveCommand::Mode::kPosition;
  else if (mode == "detach")
    c.detach = true;
  else
    r.fail(n["mode"], p + "mode", "must be 'velocity', 'position' or 'detach'");
  if (c.detach) {
    if (scene.devices[c.device].device.detach_section.empty())
      r.fail(n["mode"], p + "mode", "device '" + name + "' has no detach_section");
    return c;
  }
  c.command.insertion = r.number(n, "insertion", p, 0.0);
  c.command.rotation = r.number(n, "rotation", p, 0.0);
  const std::string why =
      validateDriveCommand(c.command, buildDeviceModel(scene.devices[c.device].device));
  if (!why.empty()) r.fail(n, p.substr(0, p.size() - 1), why);
  return c;
}

}  // namespace

std::string validateSleepOptions(const SleepOptions& o) {
  if (!(o.displacement > 0.0 && o.displacement <= 1e-4))
    return "displacement must lie in (0, 1e-4] m per step";
  if (o.steps < 1 || o.steps > 1000000) return "steps must lie in [1, 1000000]";
  return "";
}

const std::vector<std::string>& knownEffects() {
  static const std::vector<std::string> effects = {
      "gravity",  "vessel_motion", "device_contact", "subdivision",
      "friction", "coaxial",       "blood_drag",     "vessel_deformation"};
  return effects;
}

namespace {

/// `targets:` a list of vessel names, or of maps {vessel, device, depth,
/// dwell}, or {aneurysm, device, dwell}.
std::vector<TargetSpec> readTargets(const YamlReader& r, const YAML::Node& list,
                                    const SceneSpec& s) {
  if (!list.IsSequence()) r.fail(list, "targets", "must be a list of vessel names or maps");
  if (!s.vessels.present) r.fail(list, "targets", "needs vessels");
  std::vector<TargetSpec> out;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string p = "targets[" + std::to_string(i) + "]";
    const YAML::Node n = list[i];
    TargetSpec t;
    t.line = n.Mark().is_null() ? 0 : n.Mark().line + 1;
    if (n.IsScalar()) {
      t.vessel = r.text(n, p);
    } else {
      r.keys(n, p, {"vessel", "aneurysm", "device", "depth", "dwell"});
      if (n["aneurysm"]) {
        if (n["vessel"]) r.fail(n["vessel"], p + ".vessel", "a target is a vessel or an aneurysm");
        if (n["depth"]) r.fail(n["depth"], p + ".depth", "applies to a vessel target");
        t.aneurysm = r.integer(n["aneurysm"], p + ".aneurysm");
        const int count = static_cast<int>(s.vessels.aneurysms.size());
        if (t.aneurysm < 0 || t.aneurysm >= count)
          r.fail(n["aneurysm"], p + ".aneurysm",
                 "the scene's vessels have " + std::to_string(count) +
                     " aneurysm(s): an index in [0, " + std::to_string(count - 1) + "]");
        if (!n["device"]) r.fail(n, p + ".device", "an aneurysm target names the coil's device");
      } else {
        t.vessel = r.text(r.required(n, "vessel", p + ".vessel"), p + ".vessel");
      }
      if (n["device"]) {
        t.device = r.text(n["device"], p + ".device");
        bool known = false;
        for (const auto& d : s.devices) known = known || d.device.name == t.device;
        if (!known) r.fail(n["device"], p + ".device", "no device '" + t.device + "' in the scene");
      }
      t.depth = r.number(n, "depth", p + ".", t.depth);
      if (!(t.depth >= 0.0 && t.depth <= 1.0))
        r.fail(n["depth"], p + ".depth", "must lie in [0, 1] m");
      t.dwell = r.number(n, "dwell", p + ".", t.dwell);
      if (!(t.dwell >= 0.0 && t.dwell <= 60.0))
        r.fail(n["dwell"], p + ".dwell", "must lie in [0, 60] s");
    }
    out.push_back(t);
  }
  return out;
}

/// `sleep:` false, or a map {enabled, displacement, steps}.
SleepOptions readSleep(const YamlReader& r, const YAML::Node& n) {
  SleepOptions o;
  if (n.IsScalar()) {
    const std::string v = r.text(n, "sleep");
    if (v != "true" && v != "false") r.fail(n, "sleep", "must be true, false or a map");
    o.enabled = v == "true";
    return o;
  }
  r.keys(n, "sleep", {"enabled", "displacement", "steps"});
  if (n["enabled"]) {
    const std::string v = r.text(n["enabled"], "sleep.enabled");
    if (v != "true" && v != "false") r.fail(n["enabled"], "sleep.enabled", "must be true or false");
    o.enabled = v == "true";
  }
  o.displacement = r.number(n, "displacement", "sleep.", o.displacement);
  if (n["steps"]) o.steps = r.integer(n["steps"], "sleep.steps");
  const std::string why = validateSleepOptions(o);
  if (!why.empty()) r.fail(n, "sleep", why);
  return o;
}

/// `effects:`, each a known effect's name.
std::vector<std::string> readEffects(const YamlReader& r, const YAML::Node& e) {
  if (!e.IsSequence()) r.fail(e, "effects", "must be a list of effect names");
  std::vector<std::string> effects;
  for (size_t i = 0; i < e.size(); ++i) {
    const std::string name = r.text(e[i], "effects");
    const auto& known = knownEffects();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      r.fail(e[i], "effects", "unknown effect '" + name + "' (known: " + list + ")");
    }
    effects.push_back(name);
  }
  return effects;
}

/// `devices:` into s->devices (after its effects and vessels): names used
/// once, `inside` only with the effect 'coaxial', which needs one.
void readDevices(const YamlReader& r, const YAML::Node& root, const fs::path& scene_dir,
                 SceneSpec* s) {
  const YAML::Node devices = r.required(root, "devices", "devices");
  if (!devices.IsSequence() || devices.size() == 0)
    r.fail(devices, "devices", "must be a non-empty list");
  const bool coaxial =
      std::find(s->effects.begin(), s->effects.end(), "coaxial") != s->effects.end();
  bool any_inside = false;
  for (size_t i = 0; i < devices.size(); ++i) {
    const std::string key = "devices[" + std::to_string(i) + "]";
    s->devices.push_back(readDevice(r, devices[i], static_cast<int>(i), scene_dir));
    if (s->devices.back().at_inlet && !s->vessels.present)
      r.fail(devices[i]["access_point"], key + ".access_point", "inlet needs vessels");
    for (size_t j = 0; j < i; ++j)
      if (s->devices[j].device.name == s->devices[i].device.name)
        r.fail(devices[i], key + ".name",
               "device name '" + s->devices[i].device.name + "' is used twice");
    if (s->devices[i].inside.empty()) continue;
    if (!coaxial) r.fail(devices[i]["inside"], key + ".inside", "needs the effect 'coaxial'");
    resolveOuterDevice(r, devices[i], static_cast<int>(i), s);
    any_inside = true;
  }
  if (coaxial && !any_inside)
    r.fail(root["effects"], "effects", "'coaxial' needs a device with 'inside: OUTER'");
}

/// `gravity: [x, y, z]` [m/s^2] (at most 1000 m/s^2, 100 g), or `supine` /
/// `prone`: 9.81 m/s^2 toward the patient's posterior / anterior in the
/// vessels' anatomical frame (resolved when the scene is built).
void readGravity(const YamlReader& r, const YAML::Node& n, SceneSpec* s) {
  s->gravity_line = n.Mark().line + 1;
  if (n.IsScalar() && (n.Scalar() == "supine" || n.Scalar() == "prone")) {
    s->posture = n.Scalar();
    return;
  }
  if (n.IsScalar())
    r.fail(n, "gravity", "'" + n.Scalar() + "' is not [x, y, z] m/s^2, supine or prone");
  s->gravity = r.vector3(n, "gravity");
  if (!(s->gravity.norm() <= kMaxGravity)) {
    std::ostringstream why;
    why << "is " << s->gravity.norm() << " m/s^2, above " << kMaxGravity
        << " m/s^2 (100 g); the earth's is 9.81";
    r.fail(n, "gravity", why.str());
  }
}

SceneSpec readScene(const YamlReader& r) {
  const std::string& path = r.file();
  const YAML::Node root = r.load();
  // The schema first: types, ranges, unknown, duplicate and missing keys.
  std::vector<LoadError> problems;
  for (const SchemaProblem& p : checkSceneSchema(root))
    problems.emplace_back(path, p.line, p.column, p.key, p.what);
  throwLoadErrors(problems);
  if (!root.IsMap()) r.fail(root, "", "a scene is a YAML map");
  r.keys(root, "",
         {"name", "description", "time_step", "duration", "effects", "gravity", "blood_viscosity",
          "blood_density", "vessels", "contact", "sleep", "devices", "script", "targets", "xray"});
  SceneSpec s;
  s.file = path;
  s.name = r.text(r.required(root, "name", "name"), "name");
  if (root["description"]) s.description = r.text(root["description"], "description");
  s.time_step = r.number(r.required(root, "time_step", "time_step"), "time_step");
  if (!(s.time_step >= kMinTimeStep && s.time_step <= kMaxTimeStep))
    r.fail(root["time_step"], "time_step", "must lie in [1e-6, 0.04] s");

  if (root["effects"]) s.effects = readEffects(r, root["effects"]);
  if (root["gravity"]) readGravity(r, root["gravity"], &s);
  s.blood_viscosity = r.number(root, "blood_viscosity", "", s.blood_viscosity);
  if (!(s.blood_viscosity > 0.0 && s.blood_viscosity <= 0.1))
    r.fail(root["blood_viscosity"], "blood_viscosity", "must lie in (0, 0.1] Pa s");
  s.blood_density = r.number(root, "blood_density", "", s.blood_density);
  if (!(s.blood_density >= 500.0 && s.blood_density <= 2000.0))
    r.fail(root["blood_density"], "blood_density", "must lie in [500, 2000] kg/m^3");

  const fs::path scene_dir = fs::path(path).parent_path();
  if (root["vessels"]) s.vessels = readVessels(r, root["vessels"], scene_dir);
  if (root["contact"]) s.contact = readContact(r, root["contact"]);
  if (root["sleep"]) s.sleep = readSleep(r, root["sleep"]);
  if (root["xray"]) s.xray = readXray(r, root["xray"]);
  const bool moves =
      std::find(s.effects.begin(), s.effects.end(), "vessel_motion") != s.effects.end();
  if (moves && s.vessels.motion.empty())
    r.fail(root["effects"], "effects", "'vessel_motion' needs vessels.motion regions");

  readDevices(r, root, scene_dir, &s);

  if (root["script"]) {
    const YAML::Node script = root["script"];
    if (!script.IsSequence()) r.fail(script, "script", "must be a list of commands");
    for (size_t i = 0; i < script.size(); ++i)
      s.script.push_back(readCommand(r, script[i], static_cast<int>(i), s));
    std::stable_sort(
        s.script.begin(), s.script.end(),
        [](const ScriptedCommand& a, const ScriptedCommand& b) { return a.time < b.time; });
  }
  if (root["targets"]) s.targets = readTargets(r, root["targets"], s);
  s.duration = std::max(1.0, (s.script.empty() ? 0.0 : s.script.back().time) + 1.0);
  if (root["duration"]) {
    s.duration = r.number(root["duration"], "duration");
    if (!(s.duration >= s.time_step && s.duration <= kMaxDuration))
      r.fail(root["duration"], "duration", "must lie in [time_step, 3600] s");
  }
  return s;
}

}  // namespace

std::vector<SchemaProblem> checkSceneFileSchema(const std::string& path) {
  return checkSceneSchema(YamlReader(path).load());
}

namespace {

SceneSpec readSceneCatching(const YamlReader& r) {
  try {
    return readScene(r);
  } catch (const YAML::Exception& e) {  // a type yaml-cpp could not convert: never an abort
    throw LoadError(r.file(), e.mark.is_null() ? 0 : e.mark.line + 1, "", e.msg);
  }
}

}  // namespace

SceneSpec loadSceneFile(const std::string& path) { return readSceneCatching(YamlReader(path)); }

SceneSpec loadSceneText(const std::string& text, const std::string& path) {
  return readSceneCatching(YamlReader(path, text));
}

namespace {

/// The first device section whose elements are longer than the device's
/// limit, as (device index, why); (-1, "") when none is.
std::pair<int, std::string> elementLimitViolation(const SceneSpec& spec) {
  for (size_t i = 0; i < spec.devices.size(); ++i) {
    const DevicePlacementSpec& d = spec.devices[i];
    if (!(d.max_element_length > 0.0)) continue;
    for (const DeviceSectionSpec& sec : d.device.sections) {
      const double h = sec.length / std::max(1, sec.elements);
      if (h <= d.max_element_length * (1.0 + 1e-9)) continue;
      std::ostringstream why;
      why << "device '" << d.device.name << "' section '" << sec.name << "' has " << h * 1e3
          << " mm elements; scene '" << spec.name << "' allows at most "
          << d.max_element_length * 1e3 << " mm (its elements must follow the vessels' bends)";
      return {static_cast<int>(i), why.str()};
    }
  }
  return {-1, ""};
}

}  // namespace

std::string sceneLimitViolation(const SceneSpec& spec) {
  if (!(spec.time_step >= kMinTimeStep && spec.time_step <= kMaxTimeStep)) {
    std::ostringstream why;
    why << "time step " << spec.time_step << " s outside [1e-6, 0.04] s";
    return why.str();
  }
  if (!(spec.gravity.norm() <= kMaxGravity)) {
    std::ostringstream why;
    why << "gravity of " << spec.gravity.norm() << " m/s^2, above " << kMaxGravity
        << " m/s^2 (100 g)";
    return why.str();
  }
  return elementLimitViolation(spec).second;
}

void checkSceneLimits(const SceneSpec& spec) {
  if (!(spec.time_step >= kMinTimeStep && spec.time_step <= kMaxTimeStep))
    throw LoadError(spec.file, 0, "time_step", sceneLimitViolation(spec));
  if (!(spec.gravity.norm() <= kMaxGravity))
    throw LoadError(spec.file, spec.gravity_line, "gravity", sceneLimitViolation(spec));
  const auto [device, why] = elementLimitViolation(spec);
  if (device >= 0) {
    const DevicePlacementSpec& d = spec.devices[device];
    throw LoadError(spec.file, d.max_element_length_line,
                    "devices[" + std::to_string(device) + "].max_element_length", why);
  }
}

std::string configDirectory() {
  const char* env = std::getenv("EVSIM_CONFIG_DIR");
  return env && *env ? env : EVSIM_CONFIG_DIR;
}

std::string resolveScenePath(const std::string& name_or_path) {
  if (fs::exists(name_or_path) && fs::is_regular_file(name_or_path)) return name_or_path;
  const fs::path shipped = fs::path(configDirectory()) / "scenes" / (name_or_path + ".yaml");
  if (fs::exists(shipped)) return shipped.string();
  std::string list;
  for (const auto& s : shippedScenes()) list += (list.empty() ? "" : ", ") + s;
  throw LoadError(name_or_path, 0, "",
                  "no such scene file, nor a shipped scene (shipped: " + list + ")");
}

std::vector<std::string> shippedScenes() {
  std::vector<std::string> names;
  const fs::path dir = fs::path(configDirectory()) / "scenes";
  if (!fs::exists(dir)) return names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace evsim
