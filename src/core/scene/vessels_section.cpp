// The `vessels:` section of a scene file (SWC or VTK centreline, network,
// aneurysms, motion), and the vessel tree and field built from it.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/core/number_text.h"
#include "endovascular_sim/geometry/patient_frame.h"
#include "endovascular_sim/scene/centerline_scene.h"
#include "endovascular_sim/scene/centerline_vtk.h"
#include "scene_sections.h"

namespace evsim {

namespace fs = std::filesystem;

Mat3 introducerFrame(const Vec3& direction, const Vec3& up) {
  const Vec3 x = direction.normalized();
  Vec3 z = up - up.dot(x) * x;
  if (z.norm() < 1e-6) z = x.unitOrthogonal();
  z.normalize();
  Mat3 R;
  R << x, z.cross(x), z;
  return R;
}

namespace {

/// `units`: declared, never guessed (m, cm, mm or um) [m per file unit].
double readUnits(const YamlReader& r, const YAML::Node& units) {
  const double unit = lengthUnit(r.text(units, "vessels.units"));
  if (unit > 0.0) return unit;
  r.fail(units, "vessels.units", "must be m, cm, mm or um");  // (does not return)
}

/// `names`: branch id -> vessel name, each name once.
void readBranchNames(const YamlReader& r, const YAML::Node& names, CenterlineTreeOptions* tree) {
  if (!names.IsMap()) r.fail(names, "vessels.names", "must map branch ids to vessel names");
  for (const auto& kv : names) {
    const int id = r.integer(kv.first, "vessels.names");
    if (id < 0) r.fail(kv.first, "vessels.names", "branch ids are >= 0");
    const std::string name = r.text(kv.second, "vessels.names." + std::to_string(id));
    if (!isVesselName(name))
      r.fail(kv.second, "vessels.names." + std::to_string(id),
             "'" + name + "' is not a vessel name ([a-z][a-z0-9_]*)");
    if (tree->names.count(id))
      r.fail(kv.first, "vessels.names", "branch " + std::to_string(id) + " is named twice");
    tree->names[id] = name;  // a name given twice names a chain: checked with the tree
  }
}

/// The keys of a VTK centreline: radius array, simplification tolerances,
/// inlet, branch names (refused for an SWC file).
void readVtkOptions(const YamlReader& r, const YAML::Node& n, bool vtk, VesselSpec* v) {
  for (const char* key : {"radius_array", "tolerance", "radius_tolerance", "inlet", "names"})
    if (n[key] && !vtk)
      r.fail(n[key], std::string("vessels.") + key, "applies to a VTK centreline (.vtp, .vtk)");
  if (n["radius_array"]) v->radius_array = r.text(n["radius_array"], "vessels.radius_array");
  v->tree.tolerance = 1e-3 * r.number(n, "tolerance", "vessels.", v->tree.tolerance * 1e3);
  if (!(v->tree.tolerance >= 1e-6 && v->tree.tolerance <= 1e-3))
    r.fail(n["tolerance"], "vessels.tolerance", "must lie in [0.001, 1] mm");
  v->tree.radius_tolerance = r.number(n, "radius_tolerance", "vessels.", v->tree.radius_tolerance);
  if (!(v->tree.radius_tolerance >= 0.001 && v->tree.radius_tolerance <= 0.2))
    r.fail(n["radius_tolerance"], "vessels.radius_tolerance", "must lie in [0.001, 0.2]");
  if (n["inlet"]) {
    v->tree.has_inlet = true;
    v->tree.inlet = v->units * r.vector3(n["inlet"], "vessels.inlet");
  }
  if (n["names"]) readBranchNames(r, n["names"], &v->tree);
}

/// `network: {seed, vessels, min_radius}`.
void readNetwork(const YamlReader& r, const YAML::Node& g, VesselSpec* v) {
  r.keys(g, "vessels.network", {"seed", "vessels", "min_radius"});
  v->grow_network = true;
  const double seed =
      r.number(r.required(g, "seed", "vessels.network.seed"), "vessels.network.seed");
  const double count =
      r.number(r.required(g, "vessels", "vessels.network.vessels"), "vessels.network.vessels");
  if (seed < 0 || seed != std::floor(seed))
    r.fail(g["seed"], "vessels.network.seed", "must be a whole number >= 0");
  if (count < 0 || count > 100000 || count != std::floor(count))
    r.fail(g["vessels"], "vessels.network.vessels", "must be a whole number in [0, 100000]");
  v->network.seed = static_cast<uint64_t>(seed);
  v->network.vessels = static_cast<int>(count);
  v->network_line = g["vessels"].Mark().line + 1;
  v->network.min_radius = r.number(g, "min_radius", "vessels.network.", v->network.min_radius);
  if (!(v->network.min_radius > 0.0))
    r.fail(g["min_radius"], "vessels.network.min_radius", "must be positive");
}

/// `aneurysms: [{center, radius}, ...]`.
void readAneurysms(const YamlReader& r, const YAML::Node& list, VesselSpec* v) {
  if (!list.IsSequence()) r.fail(list, "vessels.aneurysms", "must be a list");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string p = "vessels.aneurysms[" + std::to_string(i) + "].";
    r.keys(list[i], p.substr(0, p.size() - 1), {"center", "radius"});
    AneurysmSpec a;
    a.center = r.vector3(r.required(list[i], "center", p + "center"), p + "center");
    a.radius = r.number(r.required(list[i], "radius", p + "radius"), p + "radius");
    if (!(a.radius > 0.0)) r.fail(list[i]["radius"], p + "radius", "must be positive");
    v->aneurysms.push_back(a);
  }
}

/// `motion: [{center, radius, amplitude, frequency, phase}, ...]`.
void readMotion(const YamlReader& r, const YAML::Node& list, VesselSpec* v) {
  if (!list.IsSequence()) r.fail(list, "vessels.motion", "must be a list of regions");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string p = "vessels.motion[" + std::to_string(i) + "].";
    r.keys(list[i], p.substr(0, p.size() - 1),
           {"center", "radius", "amplitude", "frequency", "phase"});
    MotionRegion m;
    m.center = r.vector3(r.required(list[i], "center", p + "center"), p + "center");
    m.radius = r.number(r.required(list[i], "radius", p + "radius"), p + "radius");
    m.amplitude = r.vector3(r.required(list[i], "amplitude", p + "amplitude"), p + "amplitude");
    m.frequency = r.number(r.required(list[i], "frequency", p + "frequency"), p + "frequency");
    m.phase = r.number(list[i], "phase", p, 0.0);
    if (!(m.radius > 0.0)) r.fail(list[i]["radius"], p + "radius", "must be positive");
    if (!(m.frequency > 0.0 && m.frequency <= 10.0))
      r.fail(list[i]["frequency"], p + "frequency", "must lie in (0, 10] Hz");
    if (m.amplitude.norm() > 0.03) r.fail(list[i]["amplitude"], p + "amplitude", "is above 30 mm");
    v->motion.push_back(m);
  }
}

/// The wall properties of `n` (keys of `prefix`), the rest as `fallback`.
WallProperties readWallProperties(const YamlReader& r, const YAML::Node& n,
                                  const std::string& prefix, const WallProperties& fallback) {
  WallProperties w;
  const auto read = [&](const char* key, double def, double hi, const char* unit) {
    const double x = r.number(n, key, prefix, def);
    if (!(x > 0.0 && x <= hi))
      r.fail(n[key], prefix + key,
             "must lie in (0, " + numberText(hi) + "] " + unit + ", got " + numberText(x));
    return x;
  };
  w.distensibility = read("distensibility", fallback.distensibility, 1e-3, "1/Pa");
  w.tether_stiffness = read("tether_stiffness", fallback.tether_stiffness, 1e7, "N/m^2");
  w.tether_damping = read("tether_damping", fallback.tether_damping, 1e5, "N s/m^2");
  return w;
}

/// `wall: {distensibility, tether_stiffness, tether_damping, reach,
/// vessels: [{name, distensibility, ...}]}`.
void readWall(const YamlReader& r, const YAML::Node& n, VesselSpec* v) {
  r.keys(n, "vessels.wall",
         {"distensibility", "tether_stiffness", "tether_damping", "reach", "vessels"});
  WallSpec& w = v->wall;
  w.all = readWallProperties(r, n, "vessels.wall.", WallProperties{});
  w.reach = r.number(n, "reach", "vessels.wall.", w.reach);
  if (!(w.reach > 0.0 && w.reach <= 0.02))
    r.fail(n["reach"], "vessels.wall.reach", "must lie in (0, 0.02] m, got " + numberText(w.reach));
  if (!n["vessels"]) return;
  const YAML::Node list = n["vessels"];
  if (!list.IsSequence()) r.fail(list, "vessels.wall.vessels", "must be a list");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string p = "vessels.wall.vessels[" + std::to_string(i) + "].";
    r.keys(list[i], p.substr(0, p.size() - 1),
           {"name", "distensibility", "tether_stiffness", "tether_damping"});
    WallSpec::Vessel one;
    const YAML::Node name = r.required(list[i], "name", p + "name");
    one.name = r.text(name, p + "name");
    one.line = name.Mark().line + 1;
    one.properties = readWallProperties(r, list[i], p, w.all);
    for (const WallSpec::Vessel& other : w.vessels)
      if (other.name == one.name) r.fail(name, p + "name", "'" + one.name + "' is listed twice");
    w.vessels.push_back(one);
  }
}

}  // namespace

VesselSpec readVessels(const YamlReader& r, const YAML::Node& n, const fs::path& scene_dir) {
  VesselSpec v;
  v.present = true;
  r.keys(n, "vessels",
         {"centerline", "units", "frame", "blend", "network", "aneurysms", "motion", "radius_array",
          "tolerance", "radius_tolerance", "inlet", "names", "wall"});
  const fs::path file =
      r.text(r.required(n, "centerline", "vessels.centerline"), "vessels.centerline");
  v.centerline_file = (file.is_absolute() ? file : scene_dir / file).lexically_normal().string();
  if (!fs::exists(v.centerline_file))
    r.fail(n["centerline"], "vessels.centerline", "no centreline file " + v.centerline_file);
  const bool vtk = isVtkCenterlinePath(v.centerline_file);
  if (vtk && !n["units"])
    r.fail(n["centerline"], "vessels.units",
           "a VTK centreline needs its units declared (m, cm, mm or um): SimVascular models are "
           "in cm, most VMTK output in mm");
  if (n["units"]) v.units = readUnits(r, n["units"]);
  if (n["frame"]) {
    v.frame = r.text(n["frame"], "vessels.frame");
    v.frame_line = n["frame"].Mark().line + 1;
    const std::string why = frameCodeProblem(v.frame);
    if (!why.empty()) r.fail(n["frame"], "vessels.frame", why);
  }
  readVtkOptions(r, n, vtk, &v);
  v.field.alpha = r.number(n, "blend", "vessels.", 0.6);
  if (!(v.field.alpha >= 0.3 && v.field.alpha <= 0.95))
    r.fail(n["blend"], "vessels.blend", "must lie in [0.3, 0.95]");
  if (n["network"]) readNetwork(r, n["network"], &v);
  if (n["aneurysms"]) readAneurysms(r, n["aneurysms"], &v);
  if (n["motion"]) readMotion(r, n["motion"], &v);
  if (n["wall"]) readWall(r, n["wall"], &v);
  return v;
}

Introducer inletIntroducer(const Centerline& c) {
  int root = -1, next = -1;
  for (int i = 0; i < c.numPoints() && root < 0; ++i)
    if (c.parent[i] < 0) root = i;
  if (root < 0) return {};
  // Along the first branch from the root, one root radius in: past the
  // rounded end of the surface, inside the lumen.
  const double depth = c.radius[root];
  double walked = 0.0;
  int at = root;
  while (true) {
    next = -1;
    for (int i = 0; i < c.numPoints() && next < 0; ++i)
      if (c.parent[i] == at) next = i;
    if (next < 0) break;
    const double len = (c.position[next] - c.position[at]).norm();
    if (walked + len >= depth) {
      const Vec3 dir = (c.position[next] - c.position[at]).normalized();
      Introducer intro;
      intro.access_point = c.position[at] + (depth - walked) * dir;
      intro.frame = introducerFrame(dir, dir.unitOrthogonal());
      return intro;
    }
    walked += len;
    at = next;
  }
  const int parent = c.parent[at] >= 0 ? c.parent[at] : root;
  Introducer intro;
  intro.access_point = c.position[at];
  if (parent != at)
    intro.frame = introducerFrame((c.position[at] - c.position[parent]).normalized(),
                                  (c.position[at] - c.position[parent]).unitOrthogonal());
  return intro;
}

Centerline buildCenterline(const VesselSpec& spec, std::vector<std::string>* warnings,
                           const std::string& scene_file) {
  Centerline c;
  if (isVtkCenterlinePath(spec.centerline_file)) {
    CenterlineTreeReport report;
    c = loadVtkCenterline(spec.centerline_file, {spec.units, spec.radius_array, spec.tree},
                          &report);
    if (warnings)
      for (const std::string& w : report.warnings)
        warnings->push_back(spec.centerline_file + ": " + w);
  } else {
    c = loadCenterlineFile(spec.centerline_file, spec.units);
  }
  if (spec.grow_network) {
    const int grown = growNetwork(spec.network, &c);
    if (grown < spec.network.vessels) {
      const Eigen::AlignedBox3d& box = spec.network.growth_box;
      std::ostringstream w;
      w << "only " << grown << " of the " << spec.network.vessels << " vessels asked for fit on "
        << spec.centerline_file << ": ask for at most that many, or a smaller min_radius (now "
        << spec.network.min_radius * 1e3 << " mm; only leaves of the tree inside the growth box ("
        << box.min().transpose() * 1e3 << ") to (" << box.max().transpose() * 1e3
        << ") mm and wider than it grow, and a new vessel may not cross another)";
      throw LoadError(scene_file.empty() ? spec.centerline_file : scene_file, spec.network_line,
                      "vessels.network.vessels", w.str());
    }
  }
  return c;
}

VesselField buildVesselField(const VesselSpec& spec, bool with_motion) {
  return VesselField(buildCenterline(spec), spec.aneurysms,
                     with_motion ? spec.motion : std::vector<MotionRegion>{}, spec.field);
}

}  // namespace evsim
