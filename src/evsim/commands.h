// The commands of `evsim`, each a function of its parsed options (main.cpp
// parses the command line with CLI11). Exit codes: kExitOk, kExitFailure (a
// step could not be solved, an output could not be written), kExitBadInput
// (a scene, state or option that is wrong: nothing was simulated).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace evsim {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;

/// How a bare centreline file given in place of a scene is read: its units
/// (required for VTK), its radius array, and the scene whose devices and
/// settings it gets (scene/centerline_scene.h).
struct CenterlineSource {
  std::string units;
  std::string radius_array{"MaximumInscribedSphereRadius"};
  std::string frame;  // its anatomical frame (LPS, RAS, ...; "": what the file declares)
  std::string base{"patient_example"};
};

struct RunOptions {
  std::string scene;
  CenterlineSource centerline;  // when `scene` is a centreline file
  long steps{-1};               // -1: the scene's duration
  bool json{false};
  std::string dump_lcp;    // folder for each step's last LCP ("" none)
  std::string load_state;  // state file to start from ("" none)
  std::string save_state;  // where the last good state goes ("" none)
  bool strict{false};      // fail at a step the scene's options cannot solve (no recovery)
  std::string vtk;         // folder for ParaView frames ("" none; vtk_output.h)
  double vtk_rate{25.0};   // [Hz] of simulated time between frames
};
/// `evsim run`: steps a scene, a progress line per 0.1 s or a JSON line per step.
int runScene(const RunOptions& options);

struct BenchOptions {
  std::string scene;
  long steps{-1};  // -1: the scene's duration (less the warm-up)
  long warmup{0};
  int elements{0};                     // 0: the scene's discretisation
  std::optional<std::string> effects;  // replaces the scene's effects
  long min_rows{0};                    // also report the steps with >= this many LCP rows
  bool strict{false};                  // no recovery step (see RunOptions::strict)
  bool no_sleep{false};                // every step solved, also at rest (SleepOptions)
  std::string against;                 // a second scene run whole in the same run: the ratio
  int copies{0};          // also run copies whose script speeds differ by k 1e-9 (k = 1..copies)
  int windows{0};         // also step the scene and its variants from this many of its run's states
  long window_steps{10};  // steps from each window's state
  std::vector<std::string> variants;  // scene files with the scene's devices (--variant)
};
/// `evsim bench`: step-time statistics over the whole scene and per phase.
int benchScene(const BenchOptions& options);

struct NavigateOptions {
  std::string scene;
  std::string target;      // a vessel name of the scene
  std::string device;      // whose tip must reach it ("": the innermost device)
  double timeout{90.0};    // [s] simulated
  bool json_only{false};   // only the JSON summary on stdout
  std::string steps_json;  // a file for one JSON line per step (as `evsim run --json`)
};
/// `evsim navigate`: the autopilot drives the scene's devices to a vessel; a
/// line per phase and a JSON summary. Exit 0 when reached, 1 when not.
int navigateScene(const NavigateOptions& options);

struct NavigationBenchOptions {
  std::vector<std::string> arch_scenes{"arch_to_left_subclavian", "arch_to_left_common_carotid",
                                       "arch_to_right_common_carotid", "arch_to_right_subclavian"};
  std::string network_scene{"network_navigation"};
  // The same network with the catheter for the brachiocephalic trunk's side:
  // the targets beyond the trunk are run there ("" none: all in network_scene).
  std::string network_scene_trunk{"network_navigation_headhunter"};
  int network_targets{50};  // drawn from the network (0: the arch alone)
  int anatomies{0};         // generated arches, each to its targets (evsim arch)
  std::string anatomy_dir;  // where their files go ("": a folder under the temp dir)
  int min_branchings{3};    // bifurcations passed from the access to a network target
  int max_branchings{6};
  unsigned seed{1};
  int jobs{1};           // runs at once (each on its own copy of the scene)
  double timeout{60.0};  // [s] simulated per run
  std::string csv;       // every run's row ("" none)
};
struct ArchOptions {
  unsigned long seed{1};
  int count{1};       // arches, seeds seed .. seed + count - 1
  std::string out;    // the folder of the files
  int type{0};        // 0: drawn, else 1-3
  int bovine{-1};     // -1 drawn, 0 never, 1 always
  int aberrant_rsa{-1};
};
/// `evsim arch`: generated arches as VMTK-style centrelines and their scenes.
int archCommand(const ArchOptions& options);

/// `evsim bench navigation`: the autopilot on the arch scenes' targets and
/// on targets drawn in the network; a line per run, a summary, a CSV.
int benchNavigation(const NavigationBenchOptions& options);

struct MeshOptions {
  std::string scene;
  std::string out;            // .vtp, .stl or .ply
  double spacing{0.0};        // [m], 0: automatic
  double device_radius{0.0};  // [m]
};
/// `evsim mesh`: the vessel surface as a triangle mesh.
int meshScene(const MeshOptions& options);

struct CheckOptions {
  std::vector<std::string> files;
  std::string units;  // of .vtp/.vtk (required) and .swc without a header (default mm)
  std::string scene;  // the scene a state file is checked against
};
/// `evsim check`: each file validated as its loader does; exit 2 if any is bad.
int checkFiles(const CheckOptions& options);

struct RenderOptions {
  std::string scene;
  std::string out;          // the folder of the frames
  double duration{-1.0};    // [s] simulated (-1: the scene's, or the autopilot's run)
  std::string navigate;     // a vessel: the autopilot drives there ("": the scene's script)
  double rate{0.0};         // frames per simulated second (0: the scene's xray.frame_rate)
  std::vector<double> lao;  // [deg] (empty: the scene's)
  std::vector<double> cranial;
  int pixels{0};
  std::vector<double> inject;  // START,DURATION [s]
  std::string inject_device;
  std::string inject_vessel;  // at this vessel's origin instead of a tip
  bool roadmap{false};
};
/// `evsim render`: virtual fluoroscopy of a run as PNG frames.
int renderScene(const RenderOptions& options);

/// `evsim materials`: the device materials and body media, attenuation at an energy [keV].
int materialsCommand(double energy_kev);

/// `evsim vessels`: a scene's vessel tree (branch ids for a VTK
/// centreline's names), how closely its surface keeps the radii, and what a
/// field evaluation costs.
int vesselsCommand(const std::string& scene, const CenterlineSource& centerline);

}  // namespace evsim
