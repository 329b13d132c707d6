// Every default the scene format states (the schema's `fallback`, printed
// in config/scenes/README.md) against the value the loader applies when
// the key is left out: a scene that names none of the optional keys is
// loaded and each value read back from the SceneSpec. A schema key with a
// literal default (a number, vector, bool or choice) that this test does
// not read back fails it, so a new key's default cannot go unchecked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>

#include "endovascular_sim/contact/contact_options.h"
#include "endovascular_sim/core/number_text.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/scene/scene_schema.h"

namespace evsim {
namespace {

using Read = std::function<std::string(const SceneSpec&)>;

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
std::string vec(const Vec3& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]";
}
std::string flag(bool b) { return b ? "true" : "false"; }

/// The numbers of "1e-6" or "[0, 0, 1]" (empty when it is not such a literal).
std::vector<double> numbers(const std::string& text) {
  std::string t = text;
  const bool list = !t.empty() && t.front() == '[' && t.back() == ']';
  if (list) t = t.substr(1, t.size() - 2);
  std::vector<double> out;
  std::stringstream s(t);
  std::string item;
  while (std::getline(s, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    while (end && *end == ' ') ++end;
    if (end == item.c_str() || (end && *end != '\0')) return {};
    out.push_back(v);
  }
  if (!list && out.size() != 1) return {};
  return out;
}

/// Whether the schema's fallback is a value (not prose such as "the file's").
bool literal(const SchemaEntry& e) {
  if (e.fallback.empty()) return false;
  if (e.fallback == "[]") return true;
  if (e.fallback == "true" || e.fallback == "false") return true;
  if (e.type == SchemaType::kText) return e.fallback.find(' ') == std::string::npos;  // a name
  for (const std::string& c : e.choices)
    if (c == e.fallback) return true;
  return !numbers(e.fallback).empty();
}

/// A scene naming only what it must, and one of each list entry.
SceneSpec minimalScene() {
  const std::string text =
      "name: defaults\n"
      "time_step: 0.001\n"
      "vessels:\n"
      "  centerline: ../vessels/carotid.swc\n"
      "  network: {seed: 3, vessels: 10}\n"
      "  motion:\n"
      "    - {center: [0.02, 0, 0], radius: 0.01, amplitude: [0, 0, 0.001], frequency: 1}\n"
      "  wall:\n"
      "    vessels: [{name: aortic_arch}]\n"
      "devices:\n"
      "  - file: ../devices/guidewire.urdf\n"
      "    access_point: [0.025, -0.020, -0.130]\n"
      "    insertion_direction: [1, 0, 0]\n"
      "script:\n"
      "  - {time: 0, device: guidewire}\n"
      "targets:\n"
      "  - {vessel: right_common_carotid}\n"
      "xray:\n"
      "  spine: {center: [0, 0.05, 0]}\n";
  return loadSceneText(text, configDirectory() + "/scenes/defaults_test.yaml");
}

std::map<std::string, Read> readers() {
  const double deg = 180.0 / M_PI;
  std::map<std::string, Read> r = {
      {"effects", [](const SceneSpec& s) { return s.effects.empty() ? "[]" : s.effects[0]; }},
      {"blood_viscosity", [](const SceneSpec& s) { return num(s.blood_viscosity); }},
      {"blood_density", [](const SceneSpec& s) { return num(s.blood_density); }},
      {"vessels.blend", [](const SceneSpec& s) { return num(s.vessels.field.alpha); }},
      {"vessels.radius_array", [](const SceneSpec& s) { return s.vessels.radius_array; }},
      {"vessels.tolerance",  // written in mm
       [](const SceneSpec& s) { return num(s.vessels.tree.tolerance * 1e3); }},
      {"vessels.radius_tolerance",
       [](const SceneSpec& s) { return num(s.vessels.tree.radius_tolerance); }},
      {"vessels.network.min_radius",
       [](const SceneSpec& s) { return num(s.vessels.network.min_radius); }},
      {"vessels.motion[].phase", [](const SceneSpec& s) { return num(s.vessels.motion[0].phase); }},
      {"vessels.wall.distensibility",
       [](const SceneSpec& s) { return num(s.vessels.wall.all.distensibility); }},
      {"vessels.wall.tether_stiffness",
       [](const SceneSpec& s) { return num(s.vessels.wall.all.tether_stiffness); }},
      {"vessels.wall.tether_damping",
       [](const SceneSpec& s) { return num(s.vessels.wall.all.tether_damping); }},
      {"vessels.wall.reach", [](const SceneSpec& s) { return num(s.vessels.wall.reach); }},
      {"devices[].up",
       [](const SceneSpec& s) { return vec(s.devices[0].introducer.frame.col(2)); }},
      {"devices[].inserted_length",
       [](const SceneSpec& s) { return num(s.devices[0].inserted_length); }},
      {"devices[].rotation", [](const SceneSpec& s) { return num(s.devices[0].rotation); }},
      {"devices[].drive.valve_friction",
       [](const SceneSpec& s) { return num(s.devices[0].drive.valve_friction); }},
      {"devices[].drive.valve_torque",
       [](const SceneSpec& s) { return num(s.devices[0].drive.valve_torque); }},
      {"sleep.enabled", [](const SceneSpec& s) { return flag(s.sleep.enabled); }},
      {"sleep.displacement", [](const SceneSpec& s) { return num(s.sleep.displacement); }},
      {"sleep.steps", [](const SceneSpec& s) { return num(s.sleep.steps); }},
      {"script[].mode",
       [](const SceneSpec& s) {
         return s.script[0].command.mode == DriveCommand::Mode::kVelocity ? "velocity" : "position";
       }},
      {"script[].insertion", [](const SceneSpec& s) { return num(s.script[0].command.insertion); }},
      {"script[].rotation", [](const SceneSpec& s) { return num(s.script[0].command.rotation); }},
      {"targets[].depth", [](const SceneSpec& s) { return num(s.targets[0].depth); }},
      {"targets[].device",  // "any": no device named
       [](const SceneSpec& s) {
         return s.targets[0].device.empty() ? "any" : s.targets[0].device;
       }},
      {"targets[].dwell", [](const SceneSpec& s) { return num(s.targets[0].dwell); }},
      {"xray.lao_deg", [deg](const SceneSpec& s) { return num(s.xray.c_arm.lao * deg); }},
      {"xray.cranial_deg", [deg](const SceneSpec& s) { return num(s.xray.c_arm.cranial * deg); }},
      {"xray.source_detector_distance",
       [](const SceneSpec& s) { return num(s.xray.c_arm.source_detector_distance); }},
      {"xray.source_isocenter_distance",
       [](const SceneSpec& s) { return num(s.xray.c_arm.source_isocenter_distance); }},
      {"xray.detector_size", [](const SceneSpec& s) { return num(s.xray.c_arm.detector_size); }},
      {"xray.pixels", [](const SceneSpec& s) { return num(s.xray.c_arm.pixels); }},
      {"xray.left", [](const SceneSpec& s) { return vec(s.xray.c_arm.left); }},
      {"xray.anterior", [](const SceneSpec& s) { return vec(s.xray.c_arm.anterior); }},
      {"xray.energy_kev", [](const SceneSpec& s) { return num(s.xray.energy_kev); }},
      {"xray.frame_rate", [](const SceneSpec& s) { return num(s.xray.frame_rate); }},
      {"xray.iodine_concentration",
       [](const SceneSpec& s) { return num(s.xray.iodine_concentration); }},
      {"xray.contrast_washout", [](const SceneSpec& s) { return num(s.xray.contrast_washout); }},
      {"xray.body_width", [](const SceneSpec& s) { return num(s.xray.body_width); }},
      {"xray.body_depth", [](const SceneSpec& s) { return num(s.xray.body_depth); }},
      {"xray.photons", [](const SceneSpec& s) { return num(s.xray.photons); }},
      {"xray.blur", [](const SceneSpec& s) { return num(s.xray.blur); }},
      {"xray.seed", [](const SceneSpec& s) { return num(s.xray.seed); }},
      {"xray.supersampling", [](const SceneSpec& s) { return num(s.xray.supersampling); }},
      {"xray.spine.radius", [](const SceneSpec& s) { return num(s.xray.spine.radius); }},
      {"xray.spine.vertebra", [](const SceneSpec& s) { return num(s.xray.spine.vertebra); }},
      {"xray.spine.disc", [](const SceneSpec& s) { return num(s.xray.spine.disc); }},
      {"xray.spine.bone_fraction",
       [](const SceneSpec& s) { return num(s.xray.spine.bone_fraction); }},
  };
  // contact.*: each option read back through its own accessor (a bool as
  // true/false, a choice by name), not through the table's formatting of
  // ContactOptions{} that made the schema's row.
  for (const ContactOptionField& f : contactOptionFields())
    r["contact." + f.key] = [&f](const SceneSpec& s) {
      const double v = f.get(s.contact);
      if (f.type == OptionType::kBool) return flag(v != 0.0);
      if (f.type == OptionType::kChoice) return f.choices.at(static_cast<size_t>(v));
      return num(v);
    };
  return r;
}

TEST(SchemaDefaults, EveryDefaultTheSchemaStatesIsTheOneTheLoaderApplies) {
  const SceneSpec scene = minimalScene();
  const std::map<std::string, Read> read = readers();
  int checked = 0;
  for (const SchemaEntry& e : sceneSchema()) {
    if (!literal(e)) continue;
    const auto it = read.find(e.path);
    if (it == read.end()) {
      ADD_FAILURE() << e.path << ": the schema states the default '" << e.fallback
                    << "' and this test does not read it back: add it to readers()";
      continue;
    }
    const std::string applied = it->second(scene);
    const std::vector<double> want = numbers(e.fallback), got = numbers(applied);
    if (!want.empty() && want.size() == got.size()) {
      for (size_t i = 0; i < want.size(); ++i)
        EXPECT_NEAR(got[i], want[i], 1e-12 * std::max(1.0, std::abs(want[i])))
            << e.path << ": the schema says " << e.fallback << ", the loader applies " << applied;
    } else {
      EXPECT_EQ(applied, e.fallback) << e.path;
    }
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(read.size()))
      << "readers() reads back keys that have no literal default in the schema";
}

TEST(SchemaDefaults, TheContactOptionsOutOfRangeAreRefusedByTheirKey) {
  // Each user-facing option just beyond its range (or, for a choice or a
  // bool, beyond the values it has) names its own scene key.
  for (const ContactOptionField& f : contactOptionFields()) {
    ContactOptions o;
    const double beyond = f.type == OptionType::kBool     ? 2.0
                          : f.type == OptionType::kChoice ? static_cast<double>(f.choices.size())
                                                          : f.max * 1.5 + 1.0;
    f.set(&o, beyond);
    if (f.type == OptionType::kBool) continue;  // a bool holds only true or false
    EXPECT_NE(validateContactOptions(o).find("contact." + f.key), std::string::npos)
        << f.key << " = " << beyond << ": " << validateContactOptions(o);
  }
  EXPECT_EQ(validateContactOptions(ContactOptions{}), "");
}

}  // namespace
}  // namespace evsim
