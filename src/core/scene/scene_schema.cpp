// The scene format's keys (scene/scene_schema.h): one table, read by the
// loader, `evsim check` and the generated reference in
// config/scenes/README.md. Ranges are the loader's: a value outside is
// refused before any section is read.
#include "endovascular_sim/scene/scene_schema.h"

#include <algorithm>

#include "endovascular_sim/contact/contact_options.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {
namespace {

using T = SchemaType;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A schema entry, built by chained calls.
struct Key {
  SchemaEntry e;
  Key(const char* path, SchemaType type, const char* meaning) {
    e.path = path;
    e.type = type;
    e.meaning = meaning;
  }
  Key& unit(const char* u) { return e.unit = u, *this; }
  Key& def(const char* d) { return e.fallback = d, *this; }
  Key& req() { return e.required = true, *this; }
  /// Bounds: "[]", "(]", "[)" or "()" say which ends are open.
  Key& in(const char* ends, double lo, double hi) {
    e.min = lo, e.max = hi, e.min_open = ends[0] == '(', e.max_open = ends[1] == ')';
    return *this;
  }
  Key& choices(std::vector<std::string> c) { return e.choices = std::move(c), *this; }
  Key& orAlso(SchemaType t) { return e.alternative = t, *this; }
  operator SchemaEntry() const { return e; }  // NOLINT: the table's rows
};

// One function of about 300 lines: a table, a row per key, not logic.
std::vector<SchemaEntry> makeSchema() {
  const std::vector<std::string> effects = knownEffects();
  return {
      Key("name", T::kText, "the scene's name (evsim list, the node's /stats)").req(),
      Key("description", T::kText, "one line on what the scene shows"),
      Key("time_step", T::kNumber, "the simulation's step").unit("s").req().in("[]", 1e-6, 0.04),
      Key("duration", T::kNumber,
          "the scripted procedure's length: what `evsim run` and `evsim bench` step by default "
          "(at least time_step)")
          .unit("s")
          .def("last command + 1 s, at least 1 s")
          .in("(]", 0, 3600),
      Key("effects", T::kList, "what the scene simulates; anything else is off and costs nothing")
          .def("[]"),
      Key("effects[]", T::kChoice, "an effect (see below)").choices(effects),
      Key("gravity", T::kVector3,
          "gravity, used with the effect 'gravity' (at most 1000 m/s^2); `supine` or `prone`: "
          "9.81 m/s^2 toward the patient's posterior or anterior in the vessels' frame")
          .unit("m/s^2")
          .def("supine when the vessels' frame is known, else [0, 0, -9.81]")
          .orAlso(T::kChoice)
          .choices({"supine", "prone"}),
      Key("blood_viscosity", T::kNumber,
          "the still blood's viscosity, used with the effect 'blood_drag' (docs/model.md)")
          .unit("Pa s")
          .def("3.5e-3")
          .in("(]", 0, 0.1),
      Key("blood_density", T::kNumber,
          "the still blood's density, used with the effect 'blood_drag' (docs/model.md)")
          .unit("kg/m^3")
          .def("1060")
          .in("[]", 500, 2000),

      Key("vessels", T::kMap, "the vessels; without them the scene is free space"),
      Key("vessels.centerline", T::kText,
          "the centreline file, relative to the scene: SWC (id type x y z radius parent; "
          "'# vessel: NAME ID' lines name vessels) or VTK PolyData (.vtp, .vtk: "
          "docs/patient_anatomy.md)")
          .req(),
      Key("vessels.units", T::kChoice,
          "the file's length unit: of an SWC without a '# units:' header; required for VTK")
          .choices({"m", "cm", "mm", "um"})
          .def("mm (SWC)"),
      Key("vessels.frame", T::kText,
          "the file's anatomical frame: where +x, +y, +z point in the patient (L/R, A/P, S/I; "
          "e.g. LPS, RAS); an SWC's '# frame:' line or a VTK file's field-data string 'frame' "
          "declares it too")
          .def("the file's"),
      Key("vessels.blend", T::kNumber,
          "alpha of the convolution surface: kernel width = radius / alpha")
          .def("0.6")
          .in("[]", 0.3, 0.95),
      Key("vessels.radius_array", T::kText, "VTK only: the point-data array of radii")
          .def("MaximumInscribedSphereRadius"),
      Key("vessels.tolerance", T::kNumber,
          "VTK only: the simplified axis stays this close to the file's")
          .unit("mm")
          .def("0.05")
          .in("[]", 0.001, 1),
      Key("vessels.radius_tolerance", T::kNumber,
          "VTK only: the simplified radii stay within this fraction of the file's (smoothed)")
          .def("0.03")
          .in("[]", 0.001, 0.2),
      Key("vessels.inlet", T::kVector3,
          "VTK only: the tree's end nearest this point is the inlet [file units]")
          .def("the widest end"),
      Key("vessels.names", T::kIdNames,
          "VTK only: branch id -> vessel name (`evsim vessels` lists the ids; others: branch_ID)"),
      Key("vessels.network", T::kMap, "a generated network grown on the tree's leaves"),
      Key("vessels.network.seed", T::kInteger, "of the generator").req().in("[]", 0, 1e15),
      Key("vessels.network.vessels", T::kInteger, "vessels to grow").req().in("[]", 0, 100000),
      Key("vessels.network.min_radius", T::kNumber, "the narrowest vessel grown")
          .unit("m")
          .def("0.00015")
          .in("(]", 0, 0.1),
      Key("vessels.aneurysms", T::kList, "saccular aneurysms: sphere primitives of the surface"),
      Key("vessels.aneurysms[]", T::kMap, "an aneurysm"),
      Key("vessels.aneurysms[].center", T::kVector3, "its centre").unit("m").req(),
      Key("vessels.aneurysms[].radius", T::kNumber, "its radius").unit("m").req().in("(]", 0, 0.1),
      Key("vessels.motion", T::kList, "moving regions, used with the effect 'vessel_motion'"),
      Key("vessels.motion[]", T::kMap, "a region moving sinusoidally"),
      Key("vessels.motion[].center", T::kVector3, "its centre").unit("m").req(),
      Key("vessels.motion[].radius", T::kNumber, "its radius").unit("m").req().in("(]", 0, 10),
      Key("vessels.motion[].amplitude", T::kVector3, "the displacement's amplitude (at most 30 mm)")
          .unit("m")
          .req(),
      Key("vessels.motion[].frequency", T::kNumber, "cardiac (about 1.2) or respiratory (0.25)")
          .unit("Hz")
          .req()
          .in("(]", 0, 10),
      Key("vessels.motion[].phase", T::kNumber, "phase").unit("rad").def("0"),
      Key("vessels.wall", T::kMap,
          "the wall and the tissue around it, used with the effect 'vessel_deformation' "
          "(docs/vessel_wall.md)"),
      Key("vessels.wall.distensibility", T::kNumber,
          "relative lumen area change per pressure (carotid about 1.2e-5)")
          .unit("1/Pa")
          .def("1.2e-05")
          .in("(]", 0, 1e-3),
      Key("vessels.wall.tether_stiffness", T::kNumber,
          "the surrounding tissue's pull back to rest per length and displacement")
          .unit("N/m^2")
          .def("5000")
          .in("(]", 0, 1e7),
      Key("vessels.wall.tether_damping", T::kNumber, "its damping per length and velocity")
          .unit("N s/m^2")
          .def("50")
          .in("(]", 0, 1e5),
      Key("vessels.wall.reach", T::kNumber, "the most a centreline point moves, or a radius widens")
          .unit("m")
          .def("0.002")
          .in("(]", 0, 0.02),
      Key("vessels.wall.vessels", T::kList, "named vessels with their own wall"),
      Key("vessels.wall.vessels[]", T::kMap, "a vessel's wall (unset keys: vessels.wall's)"),
      Key("vessels.wall.vessels[].name", T::kText, "the vessel's name").req(),
      Key("vessels.wall.vessels[].distensibility", T::kNumber, "as vessels.wall's")
          .unit("1/Pa")
          .in("(]", 0, 1e-3),
      Key("vessels.wall.vessels[].tether_stiffness", T::kNumber, "as vessels.wall's")
          .unit("N/m^2")
          .in("(]", 0, 1e7),
      Key("vessels.wall.vessels[].tether_damping", T::kNumber, "as vessels.wall's")
          .unit("N s/m^2")
          .in("(]", 0, 1e5),

      Key("devices", T::kList, "the devices, at least one").req(),
      Key("devices[]", T::kMap, "a device and where it enters"),
      Key("devices[].file", T::kText,
          "its URDF file, relative to the scene (config/devices/README.md)")
          .req(),
      Key("devices[].name", T::kText, "its name").def("the URDF robot's name"),
      Key("devices[].inside", T::kText,
          "effect 'coaxial': the outer device (listed before) it enters through"),
      Key("devices[].access_point", T::kVector3,
          "where it enters the body, or `inlet`: one radius into the centreline's inlet, along "
          "it; inside a lumen wide enough for it")
          .unit("m")
          .orAlso(T::kChoice)
          .choices({"inlet"}),
      Key("devices[].insertion_direction", T::kVector3, "the introducer's axis, into the body"),
      Key("devices[].up", T::kVector3, "fixes the introducer frame's z axis").def("[0, 0, 1]"),
      Key("devices[].inserted_length", T::kNumber,
          "inserted at the start, at most its length (within a relative 1e-9: a full "
          "insertion written as the nominal length is valid); laid along the vessels' path "
          "where its rest shape would leave the lumen, refused with the length that fits")
          .unit("m")
          .def("0")
          .in("[]", 0, 1000),
      Key("devices[].rotation", T::kNumber, "its rotation at the start").unit("rad").def("0"),
      Key("devices[].length", T::kNumber,
          "the device's length (a catheter of 65, 100 or 125 cm): its first (proximal) section "
          "lengthened or shortened to it, at the file's element length")
          .unit("m")
          .def("the file's")
          .in("[]", 1e-3, 10),
      Key("devices[].max_element_length", T::kNumber,
          "refine the device file's sections to at most this element length (at most 100,000 "
          "elements); also the scene's limit for coarser variants")
          .unit("m")
          .in("[]", 1e-5, kInf),
      Key("devices[].drive", T::kMap,
          "the drive's limits and the introducer valve (docs/model.md, \"Drive limits\")"),
      Key("devices[].drive.max_force", T::kNumber,
          "the drive slips beyond this axial force; `unlimited`: a kinematic drive")
          .unit("N")
          .def("the device file's (1.5 N unless it says)")
          .in("(]", 0, kInf)
          .orAlso(T::kChoice)
          .choices({"unlimited"}),
      Key("devices[].drive.max_torque", T::kNumber,
          "the drive slips beyond this torque; `unlimited`: a kinematic drive")
          .unit("N m")
          .def("the device file's (3.3 mN m unless it says)")
          .in("(]", 0, kInf)
          .orAlso(T::kChoice)
          .choices({"unlimited"}),
      Key("devices[].drive.valve_friction", T::kNumber, "the valve's axial grip against the drive")
          .unit("N")
          .def("0")
          .in("[]", 0, 100),
      Key("devices[].drive.valve_torque", T::kNumber, "the valve's grip against rotation")
          .unit("N m")
          .def("0")
          .in("[]", 0, 1),

      Key("contact", T::kMap, "the contact solver's options"),
      // contact.*: the contact options' own table (contactRows below).

      Key("sleep", T::kMap,
          "a scene at rest stops solving steps until a command (or `sleep: false`)")
          .orAlso(T::kBool),
      Key("sleep.enabled", T::kBool, "whether it may sleep").def("true"),
      Key("sleep.displacement", T::kNumber, "no node moved more than this per step ...")
          .unit("m")
          .def("1e-9")
          .in("(]", 0, 1e-4),
      Key("sleep.steps", T::kInteger, "... for this many steps in a row (and no drive moved)")
          .def("100")
          .in("[]", 1, 1e6),

      Key("script", T::kList, "commands at given times"),
      Key("script[]", T::kMap, "a command"),
      Key("script[].time", T::kNumber, "when").unit("s").req().in("[]", 0, kInf),
      Key("script[].device", T::kText, "which device (its name)").req(),
      Key("script[].mode", T::kChoice,
          "velocity: insertion [m/s], rotation [rad/s]; position: inserted length [m], angle "
          "[rad]; detach: its detach_section comes off")
          .choices({"velocity", "position", "detach"})
          .def("velocity"),
      Key("script[].insertion", T::kNumber,
          "insertion speed or target length, within the device's limits")
          .unit("m/s or m")
          .def("0"),
      Key("script[].rotation", T::kNumber,
          "rotation speed or target angle, within the device's limits")
          .unit("rad/s or rad")
          .def("0"),

      Key("targets", T::kList, "navigation targets (needs vessels; docs/navigation.md)"),
      Key("targets[]", T::kMap, "a vessel's name (any device's tip), or a map").orAlso(T::kText),
      Key("targets[].vessel", T::kText, "the vessel to reach"),
      Key("targets[].aneurysm", T::kInteger,
          "or an aneurysm (index in vessels.aneurysms): a detached coil in its sac")
          .in("[]", 0, 1e6),
      Key("targets[].device", T::kText, "whose tip counts (required for an aneurysm)").def("any"),
      Key("targets[].depth", T::kNumber,
          "past the vessel's origin (at most half a shorter vessel's length)")
          .unit("m")
          .def("0.02")
          .in("[]", 0, 1),
      Key("targets[].dwell", T::kNumber, "held there this long")
          .unit("s")
          .def("0.5")
          .in("[]", 0, 60),

      Key("xray", T::kMap, "the virtual C-arm and its images (docs/sensors.md)"),
      Key("xray.lao_deg", T::kNumber, "LAO > 0 (detector towards the patient's left), RAO < 0")
          .unit("deg")
          .def("0")
          .in("[]", -90, 90),
      Key("xray.cranial_deg", T::kNumber, "cranial > 0, caudal < 0")
          .unit("deg")
          .def("0")
          .in("[]", -60, 60),
      Key("xray.source_detector_distance", T::kNumber, "SID").unit("m").def("1.2").in("[]", 0.3, 2),
      Key("xray.source_isocenter_distance", T::kNumber,
          "source to the rotation centre (at most 0.95 SID)")
          .unit("m")
          .def("0.8")
          .in("[]", 0.1, 1.9),
      Key("xray.detector_size", T::kNumber, "the square detector's side")
          .unit("m")
          .def("0.3")
          .in("[]", 0.01, 0.6),
      Key("xray.pixels", T::kInteger, "per side").def("512").in("[]", 8, 4096),
      Key("xray.isocenter", T::kVector3, "the rotation centre")
          .unit("m")
          .def("the vessels' box centre"),
      Key("xray.left", T::kVector3, "the patient's left in the scene frame").def("[1, 0, 0]"),
      Key("xray.anterior", T::kVector3, "the patient's front (perpendicular to left)")
          .def("[0, 1, 0]"),
      Key("xray.energy_kev", T::kNumber, "effective beam energy")
          .unit("keV")
          .def("60")
          .in("[]", 35, 120),
      Key("xray.frame_rate", T::kNumber, "frames per second (7.5, 15, 30 as clinical systems)")
          .unit("1/s")
          .def("15")
          .in("[]", 0.5, 60),
      Key("xray.iodine_concentration", T::kNumber, "iodine in filled blood")
          .unit("kg/m^3")
          .def("150")
          .in("[]", 0, 400),
      Key("xray.contrast_washout", T::kNumber, "the iodine clears linearly after an injection")
          .unit("s")
          .def("1")
          .in("(]", 0, 60),
      Key("xray.body_width", T::kNumber,
          "soft tissue: an elliptic cylinder along the superior axis (0: none)")
          .unit("m")
          .def("0.32")
          .in("[]", 0, 1),
      Key("xray.body_depth", T::kNumber, "its depth").unit("m").def("0.22").in("[]", 0, 1),
      Key("xray.photons", T::kNumber, "quanta per pixel behind the body: Poisson noise (0: none)")
          .def("0")
          .in("[]", 0, 1e9),
      Key("xray.blur", T::kNumber, "Gaussian sigma of the detector's blur")
          .unit("px")
          .def("0")
          .in("[]", 0, 20),
      Key("xray.seed", T::kInteger, "of the noise").def("1").in("[]", 0, 2147483647.0),
      Key("xray.supersampling", T::kInteger, "rays per pixel side through the devices")
          .def("2")
          .in("[]", 1, 8),
      Key("xray.spine", T::kMap, "a landmark: vertebral bodies along the superior axis"),
      Key("xray.spine.center", T::kVector3, "a point on its axis").unit("m").req(),
      Key("xray.spine.radius", T::kNumber, "vertebral body radius")
          .unit("m")
          .def("0.02")
          .in("(]", 0, 0.1),
      Key("xray.spine.vertebra", T::kNumber, "vertebral body height")
          .unit("m")
          .def("0.025")
          .in("(]", 0, 0.1),
      Key("xray.spine.disc", T::kNumber, "disc height").unit("m").def("0.005").in("[]", 0, 0.05),
      Key("xray.spine.bone_fraction", T::kNumber, "of cortical bone in the body")
          .def("0.3")
          .in("(]", 0, 1),
  };
}

/// The rows of `contact:`, from the contact options' table
/// (contact/contact_options.h): its defaults are ContactOptions{}'s.
std::vector<SchemaEntry> contactRows() {
  static const SchemaType type_of[] = {T::kNumber, T::kInteger, T::kBool, T::kChoice};
  const ContactOptions defaults;
  std::vector<SchemaEntry> rows;
  for (const ContactOptionField& f : contactOptionFields()) {
    SchemaEntry e;
    e.path = "contact." + f.key;
    e.type = type_of[static_cast<int>(f.type)];
    e.unit = f.unit;
    e.fallback = formatContactOption(f, defaults);
    if (f.type == OptionType::kNumber || f.type == OptionType::kInteger) {
      e.min = f.min, e.max = f.max, e.min_open = f.min_open, e.max_open = f.max_open;
    }
    e.choices = f.choices;
    e.meaning = f.meaning;
    rows.push_back(e);
  }
  return rows;
}

std::vector<SchemaEntry> withContactRows(std::vector<SchemaEntry> rows) {
  const auto contact = std::find_if(rows.begin(), rows.end(),
                                    [](const SchemaEntry& e) { return e.path == "contact"; });
  const std::vector<SchemaEntry> options = contactRows();
  rows.insert(contact + 1, options.begin(), options.end());
  return rows;
}

}  // namespace

const std::vector<SchemaEntry>& sceneSchema() {
  static const std::vector<SchemaEntry> schema = withContactRows(makeSchema());
  return schema;
}

const std::vector<RetiredKey>& retiredSceneKeys() {
  // Switches whose two settings give the same answer (their tests prove
  // it): the faster one is always on; and the solvers' own limits.
  static const std::vector<RetiredKey> keys = {
      {"contact.interior_balls",
       "is no longer a scene key: the certified interior balls always spare field evaluations "
       "(either setting gave the same contacts); remove the key"},
      {"contact.detect_on_first_iterate",
       "is no longer a scene key: kept wall contacts are always detected on the path to the "
       "first loop's iterate (either setting gave the same answer); remove the key"},
      {"contact.columns_on_demand",
       "is no longer a scene key: the status method always forms W's columns as it reads them "
       "where that is cheaper (the same W, the same answer); remove the key"},
      {"contact.slid_pair_warm_start",
       "is no longer a scene key: a new element pair next to a kept one always takes over its "
       "force as a warm start (the LCP has one answer); remove the key"},
      {"contact.row_turn",
       "is no longer a scene key: a contact's row is formed again once its element turned by "
       "0.02 rad (forming every row in every loop gave the same answer); remove the key"},
      {"contact.regularization",
       "is no longer a scene key: the status method's regularisation is its own (1e-12 of W's "
       "largest diagonal entry); contact.tolerance sets the answer's accuracy; remove the key"},
      {"contact.friction_max_sweeps",
       "is no longer a scene key: an unsolved frictional problem subdivides the step as any "
       "unsolved step does; contact.friction_tolerance sets the accuracy; remove the key"},
  };
  return keys;
}

const RetiredKey* findRetiredKey(const std::string& path) {
  for (const RetiredKey& k : retiredSceneKeys())
    if (k.path == path) return &k;
  return nullptr;
}

}  // namespace evsim
