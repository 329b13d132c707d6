// evsim: command-line runner on the core library (no ROS). `evsim --help`
// and `evsim COMMAND --help` list the commands and their options; the
// options are parsed with CLI11. Exit codes (commands.h): 0 done, 1 a step
// failed or an output could not be written, 2 bad input (nothing run).
#include <CLI/CLI.hpp>
#include <iostream>

#include "accuracy_sweep.h"
#include "commands.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/scene/scene_schema.h"

#ifndef EVSIM_VERSION
#define EVSIM_VERSION "unknown"
#endif

namespace evsim {
namespace {

constexpr const char* kSceneHelp = "a shipped scene's name (evsim list) or a scene file's path";
constexpr const char* kSceneOrCenterlineHelp =
    "a shipped scene's name (evsim list), a scene file's path, or a centreline file (.vtp, .vtk, "
    ".swc: see --units, --base)";

/// The options of a bare centreline given in place of a scene.
void addCenterlineSource(CLI::App* command, CenterlineSource* c) {
  command->add_option("--units", c->units,
                      "a .vtp/.vtk centreline's units: m, cm, mm, um (required for them)");
  command->add_option("--radius-array", c->radius_array,
                      "its radius point-data array (default MaximumInscribedSphereRadius)");
  command->add_option("--frame", c->frame,
                      "its anatomical frame, where +x, +y, +z point in the patient (LPS, RAS, "
                      "...; default: what the file declares; needed for gravity: supine)");
  command->add_option("--base", c->base,
                      "the scene whose devices and settings it gets, entering at its inlet "
                      "(default patient_example)");
}

void addRun(CLI::App& app, RunOptions* o) {
  CLI::App* run = app.add_subcommand("run", "step a scene; a progress line per 0.1 s, or JSON");
  run->add_option("scene", o->scene, kSceneOrCenterlineHelp)->required();
  addCenterlineSource(run, &o->centerline);
  run->add_option("--steps", o->steps, "steps to run (default: the scene's duration)")
      ->check(CLI::Range(0L, 100000000L));
  run->add_flag("--json", o->json, "one JSON object per step on stdout");
  run->add_option("--dump-lcp", o->dump_lcp, "write each step's last LCP into this folder");
  run->add_option("--load-state", o->load_state, "start from a state saved by --save-state");
  run->add_option("--save-state", o->save_state,
                  "save the last good state (also after a failed step)");
  run->add_option("--vtk", o->vtk,
                  "write ParaView frames here: devices and contacts per frame, .pvd series");
  run->add_option("--vtk-rate", o->vtk_rate, "frames per simulated second (default 25)")
      ->check(CLI::Range(0.001, 100000.0));
  run->add_flag("--strict", o->strict,
                "fail at a step the scene's options cannot solve (default: retry it once with "
                "the recovery options and say so)");
}

void addNavigationBench(CLI::App* bench, NavigationBenchOptions* o) {
  CLI::App* nav = bench->add_subcommand(
      "navigation", "the autopilot on the arch's targets and on targets drawn in the network");
  nav->add_option("--arch-scenes", o->arch_scenes, "scenes whose targets are run")->delimiter(',');
  nav->add_option("--network-scene", o->network_scene, "the network scene targets are drawn in");
  nav->add_option("--network-scene-trunk", o->network_scene_trunk,
                  "the same network with the catheter for the brachiocephalic trunk: targets "
                  "beyond the trunk run there (\"\": all in --network-scene)");
  nav->add_option("--network-targets", o->network_targets, "targets drawn (0: the arch alone)")
      ->check(CLI::Range(0, 10000));
  nav->add_option("--min-branchings", o->min_branchings, "bifurcations to a target, at least")
      ->check(CLI::Range(1, 50));
  nav->add_option("--max-branchings", o->max_branchings, "and at most")->check(CLI::Range(1, 50));
  nav->add_option("--anatomies", o->anatomies,
                  "generated arches (evsim arch, seeds from --seed), each to its five targets")
      ->check(CLI::Range(0, 10000));
  nav->add_option("--anatomy-dir", o->anatomy_dir,
                  "where the generated arches' files go (default: a folder under the temp dir)");
  nav->add_option("--seed", o->seed, "seed of the draw");
  nav->add_option("--jobs", o->jobs, "runs at once")->check(CLI::Range(1, 64));
  nav->add_option("--timeout", o->timeout, "simulated seconds per run")
      ->check(CLI::Range(0.01, 3600.0));
  nav->add_option("--csv", o->csv, "write every run's row here");
}

void addBench(CLI::App& app, BenchOptions* o, std::string* what, double* duration, std::string* csv,
              NavigationBenchOptions* nav) {
  CLI::App* bench = app.add_subcommand(
      "bench",
      "step times over the scene's whole procedure and per phase (free, contact, "
      "inserted), with the real-time factor");
  bench->add_option("scene", o->scene, kSceneHelp);
  bench->add_option("--steps", o->steps, "steps measured (default: to the scene's duration)")
      ->check(CLI::Range(1L, 100000000L));
  bench->add_option("--warmup", o->warmup, "steps run before measuring")
      ->check(CLI::Range(0L, 100000000L));
  bench->add_option("--elements", o->elements, "about this many elements per device")
      ->check(CLI::Range(1, 20000));
  bench->add_option("--effects", o->effects, "replace the scene's effects (A,B,...; \"\" none)");
  bench
      ->add_option("--min-rows", o->min_rows,
                   "also report the steps whose last LCP has at least this many rows")
      ->check(CLI::Range(1L, 1000000L));
  bench->add_option("--against", o->against,
                    "a second scene, run whole in the same run: the medians' ratio printed");
  bench
      ->add_option("--copies", o->copies,
                   "also run N copies whose script speeds differ by k 1e-9 (k = 1..N): the "
                   "spread of a chaotic scene's figures")
      ->check(CLI::Range(0, 20));
  bench
      ->add_option("--windows", o->windows,
                   "also step the scene, and each --variant, from N states of its run spread "
                   "over the measured stretch: a paired comparison where the path is chaotic")
      ->check(CLI::Range(1, 1000));
  bench->add_option("--window-steps", o->window_steps, "steps from each window's state")
      ->check(CLI::Range(1L, 100000L));
  bench->add_option("--variant", o->variants,
                    "with --windows: a scene file with the scene's devices (other options)");
  bench->add_flag("--strict", o->strict, "no recovery step: fail where the scene's options do");
  bench->add_flag("--no-sleep", o->no_sleep,
                  "solve every step, also once the scene is at rest (scene key sleep)");
  CLI::App* accuracy =
      bench->add_subcommand("accuracy", "what each accuracy knob costs, against a fine run");
  accuracy->add_option("what", *what, "SCENE, beam or root")->required();
  accuracy->add_option("--duration", *duration, "simulated seconds per run")
      ->check(CLI::Range(1e-3, 60.0));
  accuracy->add_option("--csv", *csv, "write the rows here instead of stdout");
  addNavigationBench(bench, nav);
}

void addMesh(CLI::App& app, MeshOptions* o) {
  CLI::App* mesh = app.add_subcommand("mesh", "the vessel surface as a triangle mesh");
  mesh->add_option("scene", o->scene, kSceneHelp)->required();
  mesh->add_option("--out", o->out, "output file, .vtp (ParaView), .stl or .ply")->required();
  mesh->add_option("--spacing", o->spacing, "grid spacing [m] (0: automatic)")
      ->check(CLI::Range(0.0, 0.01) &
              CLI::Validator(
                  [](std::string& v) {
                    return std::stod(v) == 0.0 || std::stod(v) >= 1e-4
                               ? std::string()
                               : std::string("0 or at least 1e-4 m (finer meshes are too large)");
                  },
                  "0 or >= 1e-4"));
  mesh->add_option("--device-radius", o->device_radius, "offset the wall inward by [m]")
      ->check(CLI::Range(0.0, 0.005));
}

void addNavigate(CLI::App& app, NavigateOptions* o) {
  CLI::App* nav = app.add_subcommand(
      "navigate", "the autopilot drives the devices to a named vessel; a JSON summary");
  nav->add_option("scene", o->scene, kSceneHelp)->required();
  nav->add_option("--target", o->target,
                  "the vessel to reach (a name of the scene's vessels; default: the scene's "
                  "first target)");
  nav->add_option("--device", o->device,
                  "whose tip must reach it (default: the target's device, else the innermost)");
  nav->add_option("--timeout", o->timeout, "simulated seconds before giving up")
      ->check(CLI::Range(0.01, 3600.0));
  nav->add_flag("--quiet", o->json_only, "print only the JSON summary");
  nav->add_option("--steps-json", o->steps_json,
                  "write one JSON line per step to this file (the fields of evsim run --json)");
}

void addRender(CLI::App& app, RenderOptions* o) {
  CLI::App* render = app.add_subcommand(
      "render", "virtual fluoroscopy of a run: PNG frames at the X-ray frame rate");
  render->add_option("scene", o->scene, kSceneHelp)->required();
  render->add_option("--out", o->out, "the folder of the frames and camera_info.yaml")->required();
  render
      ->add_option("--duration", o->duration,
                   "simulated seconds (default: the scene's; with --navigate: the autopilot's "
                   "run, or to this time with the devices then held)")
      ->check(CLI::Range(1e-3, 3600.0));
  render->add_option("--navigate", o->navigate,
                     "the autopilot drives to this vessel instead of the scene's script");
  render->add_option("--rate", o->rate, "frames per simulated second (default: the scene's, 15)")
      ->check(CLI::Range(0.5, 60.0));
  render->add_option("--lao", o->lao, "C-arm angle [deg]: LAO > 0, RAO < 0")
      ->expected(1)
      ->check(CLI::Range(-90.0, 90.0));
  render->add_option("--cranial", o->cranial, "C-arm tilt [deg]: cranial > 0, caudal < 0")
      ->expected(1)
      ->check(CLI::Range(-60.0, 60.0));
  render->add_option("--pixels", o->pixels, "detector pixels per side")->check(CLI::Range(8, 4096));
  render->add_option("--inject", o->inject, "inject contrast: START,DURATION [s]")
      ->delimiter(',')
      ->expected(2);
  render->add_option("--inject-device", o->inject_device,
                     "at whose tip the contrast leaves (default: the first device)");
  render->add_option("--inject-vessel", o->inject_vessel,
                     "or 5 mm into this vessel (an aortogram: ascending_aorta)");
  render->add_flag("--roadmap", o->roadmap,
                   "after the injection, show its angiogram under the live image");
}

void addCheck(CLI::App& app, CheckOptions* o) {
  CLI::App* check = app.add_subcommand(
      "check", "validate scene, device, centreline and state files without running them");
  check->add_option("files", o->files, "the files (.yaml, .urdf, .swc, .vtp, .vtk, state)")
      ->required();
  check->add_option("--units", o->units,
                    "units of a .vtp/.vtk centreline (m, cm, mm, um; required for them)");
  check->add_option("--scene", o->scene, "the scene a state file belongs to");
}

int dispatch(int argc, char** argv) {
  CLI::App app{"evsim: catheter, guidewire and coil navigation in vessels (no ROS)", "evsim"};
  app.set_version_flag("--version", std::string("evsim ") + EVSIM_VERSION);
  app.require_subcommand(1);
  RunOptions run;
  BenchOptions bench;
  MeshOptions mesh;
  NavigateOptions navigate;
  NavigationBenchOptions navigation_bench;
  std::string what, csv;
  double duration = 2.0;
  addRun(app, &run);
  addBench(app, &bench, &what, &duration, &csv, &navigation_bench);
  addMesh(app, &mesh);
  addNavigate(app, &navigate);
  RenderOptions render;
  addRender(app, &render);
  double energy_kev = 60.0;
  app.add_subcommand("materials",
                     "the radiopaque materials of device files and their X-ray attenuation")
      ->add_option("--energy", energy_kev, "effective beam energy [keV]")
      ->check(CLI::Range(35.0, 120.0));
  app.add_subcommand("list", "the shipped scenes");
  app.add_subcommand("schema",
                     "the scene format's keys (type, unit, default, range, meaning) as Markdown");
  CheckOptions check;
  addCheck(app, &check);
  ArchOptions arch;
  CLI::App* arch_command = app.add_subcommand(
      "arch", "generated aortic arches (types I-III, bovine, aberrant right subclavian) as "
              "VMTK-style centrelines and their scenes");
  arch_command->add_option("--seed", arch.seed, "the first arch's seed");
  arch_command->add_option("--count", arch.count, "arches, seeds --seed onward")
      ->check(CLI::Range(1, 10000));
  arch_command->add_option("--out", arch.out, "the folder of the files")->required();
  arch_command->add_option("--type", arch.type, "arch type 1-3 (default: drawn)")
      ->check(CLI::Range(1, 3));
  arch_command->add_option("--bovine", arch.bovine, "1 always, 0 never (default: drawn)")
      ->check(CLI::Range(0, 1));
  arch_command->add_option("--aberrant-subclavian", arch.aberrant_rsa,
                           "1 always, 0 never (default: drawn)")
      ->check(CLI::Range(0, 1));
  std::string vessels_scene;
  CenterlineSource vessels_centerline;
  CLI::App* vessels = app.add_subcommand(
      "vessels", "a scene's vessel tree, its branch ids, the surface's fidelity to the radii");
  vessels->add_option("scene", vessels_scene, kSceneOrCenterlineHelp)->required();
  addCenterlineSource(vessels, &vessels_centerline);
  const auto known =
      app.get_subcommands([&](const CLI::App* c) { return argc > 1 && c->get_name() == argv[1]; });
  if (argc > 1 && argv[1][0] != '-' && known.empty()) {
    std::cerr
        << "evsim: unknown command '" << argv[1]
        << "' (run, bench, navigate, render, materials, mesh, vessels, check, arch, list, schema; "
           "evsim "
           "--help)\n";
    return kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help, the version or the error
    return code == 0 ? kExitOk : kExitBadInput;
  }
  if (app.got_subcommand("run")) return runScene(run);
  if (app.got_subcommand("mesh")) return meshScene(mesh);
  if (app.got_subcommand("navigate")) return navigateScene(navigate);
  if (app.got_subcommand("render")) return renderScene(render);
  if (app.got_subcommand("materials")) return materialsCommand(energy_kev);
  if (app.got_subcommand("vessels")) return vesselsCommand(vessels_scene, vessels_centerline);
  if (app.got_subcommand("check")) return checkFiles(check);
  if (app.got_subcommand("arch")) return archCommand(arch);
  if (app.got_subcommand("schema")) {
    std::cout << sceneSchemaMarkdown();
    return kExitOk;
  }
  if (app.got_subcommand("list")) {
    for (const auto& s : shippedScenes()) std::cout << s << "\n";
    return kExitOk;
  }
  CLI::App* b = app.get_subcommand("bench");
  if (b->got_subcommand("accuracy")) return accuracyCommand(what, duration, csv);
  if (b->got_subcommand("navigation")) {
    if (navigation_bench.min_branchings > navigation_bench.max_branchings) {
      std::cerr << "evsim bench navigation: --min-branchings exceeds --max-branchings\n";
      return kExitBadInput;
    }
    return benchNavigation(navigation_bench);
  }
  if (bench.scene.empty()) {
    std::cerr << "evsim bench: needs a SCENE (or 'accuracy'); evsim bench --help\n";
    return kExitBadInput;
  }
  return benchScene(bench);
}

}  // namespace
}  // namespace evsim

int main(int argc, char** argv) {
  try {
    return evsim::dispatch(argc, argv);
  } catch (const evsim::LoadError& e) {
    std::cerr << "evsim: " << e.what() << "\n";
    return evsim::kExitBadInput;
  } catch (const std::exception& e) {  // (a bug: say so rather than abort)
    std::cerr << "evsim: internal error: " << e.what() << "\n";
    return evsim::kExitFailure;
  }
}
