// Scene files (YAML): time step, effects, devices and where they enter, and
// an optional script of commands. See config/scenes/README.md.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/geometry/centerline_tree.h"
#include "endovascular_sim/geometry/network_generator.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "endovascular_sim/geometry/vessel_wall.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/introducer.h"
#include "endovascular_sim/scene/xray_spec.h"

namespace evsim {

struct DevicePlacementSpec {
  std::string file;  // resolved device file path
  DeviceSpec device;
  Introducer introducer;
  double inserted_length{0.0};  // at start [m]
  double rotation{0.0};         // at start [rad]
  DriveSpec drive;              // `drive: {max_force, max_torque, valve_friction, valve_torque}`
  std::string inside;           // effect 'coaxial': the outer device's name ("" none)
  int outer{-1};                // its index; the introducer is the outer device's
  /// The scene's limit on this device's element length [m] (0: none), and
  /// the scene file's line that states it: the loader refines the device
  /// file's sections to it, and checkSceneLimits refuses a coarser variant.
  double max_element_length{0.0};
  int max_element_length_line{0};
  int access_point_line{0};  // the scene file's line of access_point (0: none)
  int inserted_length_line{0};
  bool at_inlet{false};  // `access_point: inlet`: placed by inletIntroducer when built
};

/// A navigation target (`targets:`; see sim/targets.h).
struct TargetSpec {
  std::string vessel;  // a vessel name of the scene's centreline ("": an aneurysm target)
  int aneurysm{-1};    // or an aneurysm (index in vessels.aneurysms): a detached coil inside it
  std::string device;  // whose tip counts ("": any device; required for an aneurysm)
  double depth{0.02};  // [m] past the vessel's origin
  double dwell{0.5};   // [s] the tip (the coil) stays there
  int line{0};         // the scene file's line (errors)
  /// What it names: the vessel, or "aneurysm K".
  std::string label() const {
    return aneurysm >= 0 ? "aneurysm " + std::to_string(aneurysm) : vessel;
  }
};

struct ScriptedCommand {
  double time{0.0};  // [s] from the start
  int device{0};     // index into the scene's devices
  DriveCommand command;
  bool detach{false};  // mode 'detach': the device's detach_section comes off (no drive change)
};

/// When the scene sleeps (`sleep:`; MuJoCo, Bullet and PhysX call it so):
/// once no drive moves and no node has moved more than `displacement` in
/// each of `steps` consecutive steps, step() only advances the clock,
/// keeping the state (velocities zeroed) and the last contacts with their
/// forces, until a command that changes a drive, a scripted command or a
/// detachment wakes it. Never with the effect 'vessel_motion' (the walls
/// move). What it costs in accuracy: `evsim bench accuracy`.
struct SleepOptions {
  bool enabled{true};
  double displacement{1e-9};  // [m] per step, of every node (a rotation: times its element)
  int steps{100};             // consecutive resting steps before the scene sleeps
};

/// Why sleep options are out of range ("" when valid).
std::string validateSleepOptions(const SleepOptions& o);

/// The vessels of a scene (none: free space).
/// `vessels.wall`: the wall and its surroundings, for the effect
/// 'vessel_deformation' (geometry/vessel_wall.h).
struct WallSpec {
  WallProperties all;  // every vessel the list does not name
  double reach{2e-3};  // [m] the most a centreline point moves or a radius widens
  struct Vessel {
    std::string name;
    WallProperties properties;
    int line{0};  // of its `name`
  };
  std::vector<Vessel> vessels;  // per named vessel, checked against the vessels when built
};

struct VesselSpec {
  bool present{false};
  std::string centerline_file;  // resolved path: SWC, or VTK PolyData (.vtp, .vtk)
  double units{1e-3};           // [m] per file unit (SWC: without a header; VTK: declared)
  std::string frame;            // `vessels.frame`: anatomical orientation code ("": the file's)
  int frame_line{0};
  int network_line{0};  // of vessels.network.vessels (0: none)
  // A VTK centreline (scene/centerline_vtk.h): the radius array, the tree's
  // tolerances, its inlet and branch names.
  std::string radius_array{"MaximumInscribedSphereRadius"};
  CenterlineTreeOptions tree;
  VesselFieldOptions field;  // blend alpha
  bool grow_network{false};
  NetworkOptions network;
  std::vector<AneurysmSpec> aneurysms;
  std::vector<MotionRegion> motion;  // used with effect 'vessel_motion'
  WallSpec wall;                     // used with effect 'vessel_deformation'
};

struct SceneSpec {
  std::string file;
  std::string name;
  std::string description;
  double time_step{1e-3};            // [s]
  std::vector<std::string> effects;  // names, validated
  Vec3 gravity{0.0, 0.0, -9.81};     // [m/s^2], used with effect 'gravity'
  std::string posture;               // `gravity: supine|prone` ("": the vector above)
  int gravity_line{0};               // of the `gravity` key (0: absent)
  double blood_viscosity{3.5e-3};    // [Pa s], used with effect 'blood_drag'
  double blood_density{1060.0};      // [kg/m^3], used with effect 'blood_drag'
  VesselSpec vessels;
  ContactOptions contact;
  SleepOptions sleep;
  std::vector<DevicePlacementSpec> devices;
  std::vector<ScriptedCommand> script;  // sorted by time
  std::vector<TargetSpec> targets;  // navigation targets (checked against the vessels when built)
  XraySpec xray;                    // the X-ray system (`xray:`), for the images
  /// Length of the scripted procedure [s]: what `evsim bench` and the
  /// node's benchmark run by default. The file's `duration`, else the last
  /// command's time + 1 s (at least 1 s).
  double duration{1.0};
};

/// Builds the centreline (with its generated network) and the field of a
/// scene's vessels; `with_motion` adds the motion regions.
/// The introducer at a centreline's inlet (its first root): one root
/// radius along the first branch, pointing along it.
Introducer inletIntroducer(const Centerline& centerline);

/// Warnings about a usable but suspect tree (a VTK centreline's dropped
/// pieces, crowded branches) go to *warnings when given. A network that
/// cannot grow the vessels asked for is a LoadError naming `scene_file`
/// (default: the centreline file), its line and how many fit.
Centerline buildCenterline(const VesselSpec& spec, std::vector<std::string>* warnings = nullptr,
                           const std::string& scene_file = "");
VesselField buildVesselField(const VesselSpec& spec, bool with_motion);

/// Effects a scene may name.
const std::vector<std::string>& knownEffects();

/// Reads and validates a scene and the device files it names. Throws
/// LoadError naming the file, the line and the field.
SceneSpec loadSceneFile(const std::string& path);

/// loadSceneFile of a scene given as YAML text; `path` stands for its file:
/// its folder resolves the relative paths in it, its name is in every error.
SceneSpec loadSceneText(const std::string& text, const std::string& path);

/// Why a scene (possibly changed after loading: `evsim bench --elements`,
/// the accuracy sweep) is beyond the limits it states: a time step outside
/// (0, 0.04] s, or a device with elements longer than its
/// max_element_length. "" when it is within them.
std::string sceneLimitViolation(const SceneSpec& spec);

/// Throws LoadError (the scene file, the line of the limit, the field) when
/// sceneLimitViolation is not empty.
void checkSceneLimits(const SceneSpec& spec);

/// Folder of the shipped configuration (devices/, scenes/): $EVSIM_CONFIG_DIR
/// or the package's config/.
std::string configDirectory();

/// A path as is, or the name of a shipped scene (config/scenes/NAME.yaml).
/// Throws LoadError when neither exists.
std::string resolveScenePath(const std::string& name_or_path);

/// Names of the shipped scenes, sorted.
std::vector<std::string> shippedScenes();

}  // namespace evsim
