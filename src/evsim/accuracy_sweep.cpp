// `evsim bench accuracy`: what each accuracy knob costs in time. Declared and
// documented in accuracy_sweep.h.
#include "accuracy_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/mechanics/static_equilibrium.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "scene_variants.h"

namespace evsim {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Row {
  std::string knob, setting;
  double cost{0.0};
  std::string cost_unit;
  double error_m{0.0};
  double max_penetration_m{0.0};
  double max_residual{0.0};
  long rejected{0};
};

void writeRows(const std::vector<Row>& rows, std::ostream& out) {
  out << "knob,setting,cost,cost_unit,error_m,max_penetration_m,max_residual,rejected\n";
  for (const Row& r : rows) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%.6g,%s,%.6g,%.6g,%.6g,%ld\n", r.knob.c_str(),
                  r.setting.c_str(), r.cost, r.cost_unit.c_str(), r.error_m, r.max_penetration_m,
                  r.max_residual, r.rejected);
    out << line;
  }
}

// --- the whole scene ---------------------------------------------------------

struct RunResult {
  std::vector<Vec3> tips;  // of every device at the end [m]
  double wall_s{0.0};
  double max_penetration_m{0.0};
  double max_residual{0.0};
  long rejected{0};
};

/// Runs the scene to `duration` simulated seconds with the knob's own
/// options, no recovery: a rejected step is counted and tried again (at
/// most 4x the steps).
RunResult runScene(const SceneSpec& spec, double duration) {
  const SceneModel model = buildSceneModel(spec);
  SimData data = makeData(model);
  RunResult r;
  const long max_steps = 4 * static_cast<long>(std::ceil(duration / model.time_step)) + 10;
  const auto t0 = Clock::now();
  for (long k = 0; k < max_steps && data.time < duration - 1e-9; ++k) {
    if (step(model, &data) != StepStatus::kOk) {
      ++r.rejected;
      continue;
    }
    r.max_penetration_m = std::max(r.max_penetration_m, data.stats.contact.max_penetration_m);
    r.max_residual = std::max(r.max_residual, data.stats.contact.lcp_residual);
  }
  r.wall_s = secondsSince(t0);
  for (const auto& d : data.devices) r.tips.push_back(d.position.back());
  return r;
}

struct Setting {
  std::string knob, value;
  std::function<void(SceneSpec*)> apply;
};

std::vector<Setting> sceneSettings(const SceneSpec& base) {
  std::vector<Setting> s;
  const auto contact = [](auto f) { return [f](SceneSpec* sp) { f(&sp->contact); }; };
  s.push_back({"baseline", "scene", [](SceneSpec*) {}});
  s.push_back({"solver", "status",
               contact([](ContactOptions* o) { o->lcp.solver = LcpSolver::kStatusMethod; })});
  s.push_back(
      {"solver", "lemke", contact([](ContactOptions* o) { o->lcp.solver = LcpSolver::kLemke; })});
  for (int sweeps : {5, 20, 100, 1000})
    s.push_back({"solver", "pgs_" + std::to_string(sweeps), contact([sweeps](ContactOptions* o) {
                   o->lcp.solver = LcpSolver::kPgs;
                   o->lcp.max_iterations = sweeps;
                 })});
  for (double tol : {1e-6, 1e-9, 1e-14}) {
    std::ostringstream v;
    v << tol;
    s.push_back(
        {"lcp_tolerance", v.str(), contact([tol](ContactOptions* o) { o->lcp.tolerance = tol; })});
  }
  if (std::find(base.effects.begin(), base.effects.end(), "friction") !=
      base.effects.end()) {  // the frictional solvers replace the LCP's
    s.push_back({"friction_solver", "newton", contact([](ContactOptions* o) {
                   o->friction_solver.solver = FrictionSolver::kNewton;
                 })});
    for (int sweeps : {10, 100, 1000})
      s.push_back({"friction_solver", "nsgs_" + std::to_string(sweeps),
                   contact([sweeps](ContactOptions* o) {
                     o->friction_solver.solver = FrictionSolver::kNsgs;
                     o->friction_solver.max_sweeps = sweeps;
                   })});
    for (double tol : {1e-4, 1e-6, 1e-8}) {
      std::ostringstream v;
      v << tol;
      s.push_back({"friction_tolerance", v.str(),
                   contact([tol](ContactOptions* o) { o->friction_solver.tolerance = tol; })});
    }
  }
  for (double tol : {1e-4, 1e-5, 1e-7, 1e-8}) {
    std::ostringstream v;
    v << tol;
    s.push_back({"penetration_tolerance", v.str(),
                 contact([tol](ContactOptions* o) { o->penetration_tolerance = tol; })});
  }
  const auto& fx = base.effects;
  if (std::find(fx.begin(), fx.end(), "device_contact") != fx.end())  // how far surfaces overlap
    for (double tol : {5e-6, 2e-5}) {
      std::ostringstream v;
      v << tol;
      s.push_back({"pair_tolerance", v.str(),
                   contact([tol](ContactOptions* o) { o->pair_tolerance = tol; })});
    }
  for (int loops : {1, 2, 3, 5, 30})
    s.push_back({"activation_loops", std::to_string(loops),
                 contact([loops](ContactOptions* o) { o->max_activation_loops = loops; })});
  // The wall's curvature term updated in the first loop only, or three
  // (the default: every loop). It shapes the loop's path, not its answer.
  for (int loops : {1, 3})
    s.push_back({"curvature_loops", std::to_string(loops),
                 contact([loops](ContactOptions* o) { o->curvature_loops = loops; })});
  // The lumen's curvature springs: how settled the loop ends.
  if (std::find(fx.begin(), fx.end(), "coaxial") != fx.end()) {
    for (double tol : {1e-6, 2e-5}) {  // how far beyond the lumen a point may end
      std::ostringstream v;
      v << tol;
      s.push_back({"lumen_tolerance", v.str(),
                   contact([tol](ContactOptions* o) { o->lumen_tolerance = tol; })});
    }
    for (double settle : {1e-3, 0.03, 0.3}) {
      std::ostringstream v;
      v << settle;
      s.push_back({"lumen_settle", v.str(),
                   contact([settle](ContactOptions* o) { o->lumen_settle = settle; })});
    }
  }
  for (int sub : {0, 2, 8})
    s.push_back({"subdivisions", std::to_string(sub),
                 contact([sub](ContactOptions* o) { o->max_subdivisions = sub; })});
  for (double tol : {1e-6, 1e-8, 1e-9}) {
    std::ostringstream v;
    v << tol;
    s.push_back({"root_tolerance", v.str(),
                 contact([tol](ContactOptions* o) { o->root.tolerance = tol; })});
  }
  const int elements = elementCount(base);
  for (double f : {0.5, 1.5, 2.0}) {
    const int e = static_cast<int>(std::lround(f * elements));
    s.push_back({"elements", std::to_string(e), [e](SceneSpec* sp) { setElementCount(sp, e); }});
  }
  for (double f : {0.5, 2.0, 5.0}) {
    const double dt = f * base.time_step;
    std::ostringstream v;
    v << dt * 1e3 << "ms";
    s.push_back({"time_step", v.str(), [dt](SceneSpec* sp) { sp->time_step = dt; }});
  }
  return s;
}

/// The reference: a quarter of the time step, twice the elements, tight
/// tolerances, many loops.
SceneSpec referenceSpec(SceneSpec spec) {
  spec.time_step /= 4.0;
  setElementCount(&spec, 2 * elementCount(spec));
  spec.contact.lcp.solver = LcpSolver::kStatusMethod;
  spec.contact.penetration_tolerance = 1e-8;
  spec.contact.pair_tolerance = 0.0;  // (the wall's)
  spec.contact.lumen_tolerance = 1e-8;
  spec.contact.max_activation_loops = 50;
  spec.contact.max_subdivisions = 8;
  spec.contact.root.tolerance = 1e-12;
  spec.contact.friction_solver.solver = FrictionSolver::kNewton;
  spec.contact.friction_solver.tolerance = 1e-12;
  spec.contact.friction_solver.max_sweeps = 100000;
  return spec;
}

double tipError(const RunResult& run, const RunResult& reference) {
  double e = 0.0;
  for (size_t i = 0; i < run.tips.size() && i < reference.tips.size(); ++i)
    e = std::max(e, (run.tips[i] - reference.tips[i]).norm());
  return e;
}

std::vector<Row> sweepScene(const std::string& scene, double duration) {
  const SceneSpec base = loadSceneFile(resolveScenePath(scene));
  std::cerr << "reference run of " << scene << " (" << duration << " s simulated)...\n";
  const RunResult reference = runScene(referenceSpec(base), duration);
  std::cerr << "  took " << reference.wall_s << " s\n";
  std::vector<Row> rows;
  for (const Setting& s : sceneSettings(base)) {
    SceneSpec spec = base;
    s.apply(&spec);
    if (!validateContactOptions(spec.contact).empty()) continue;
    if (const std::string why = sceneLimitViolation(spec); !why.empty()) {
      std::cerr << "  " << s.knob << "=" << s.value << ": refused, " << why << "\n";
      continue;
    }
    const RunResult run = runScene(spec, duration);
    Row r;
    r.knob = s.knob;
    r.setting = s.value;
    r.cost = run.wall_s / duration;  // wall seconds per simulated second
    r.cost_unit = "s_per_sim_s";
    r.error_m = tipError(run, reference);
    r.max_penetration_m = run.max_penetration_m;
    r.max_residual = run.max_residual;
    r.rejected = run.rejected;
    std::cerr << "  " << r.knob << "=" << r.setting << ": " << r.cost << " s/s, tip error "
              << r.error_m * 1e3 << " mm, penetration " << r.max_penetration_m * 1e6
              << " um, residual " << r.max_residual << ", rejected " << r.rejected << "\n";
    rows.push_back(r);
  }
  return rows;
}

// --- the beam discretisation alone -------------------------------------------

std::vector<Row> sweepBeam() {
  const DeviceSpec wire = loadDeviceFile(configDirectory() + "/devices/guidewire.urdf");
  const BeamSection section = wire.sections.front().section;  // the shaft
  const double length = 0.1;                                  // [m]
  const double EI = section.young_modulus * section.secondMoment();
  const double P = 5.0 * EI / (length * length);  // PL^2/EI = 5: large rotations
  const auto tip = [&](int elements) {
    const DeviceModel model =
        buildDeviceModel(straightDeviceSpec("beam", section, length, elements));
    DeviceState state = restState(model);
    std::vector<Vec6> wrenches(model.num_nodes, Vec6::Zero());
    wrenches.back() << 0.0, -P, 0.0, 0.0, 0.0, 0.0;
    StaticOptions options;
    options.load_steps = 20;
    solveStaticEquilibrium(model, 1, wrenches, options, &state);
    return state.position.back();
  };
  const Vec3 reference = tip(800);
  std::vector<Row> rows;
  for (int elements : {2, 4, 8, 16, 32, 64, 128, 256}) {
    const DeviceModel model =
        buildDeviceModel(straightDeviceSpec("beam", section, length, elements));
    Introducer intro;
    DeviceState state = placeDevice(model, intro, model.length, 0.0);
    DeviceWorkspace ws;
    const int steps = 200;
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k)
      computeFreeMotion(model, intro, Vec3(0.0, 0.0, -9.81), 1e-3, state, &ws);
    Row r;
    r.knob = "beam_elements";
    r.setting = std::to_string(elements);
    r.cost = 1e3 * secondsSince(t0) / steps;
    r.cost_unit = "ms_per_step";
    r.error_m = (tip(elements) - reference).norm();
    std::cerr << "  " << elements << " elements: " << r.cost << " ms per step, tip error "
              << r.error_m * 1e3 << " mm (beam 100 mm, PL^2/EI = 5)\n";
    rows.push_back(r);
  }
  return rows;
}

// --- the first-root search alone ----------------------------------------------

std::vector<Row> sweepRoot() {
  const SceneSpec spec = loadSceneFile(resolveScenePath("carotid"));
  const VesselField field = buildVesselField(spec.vessels, false);
  // Segments from inside the lumen (near centreline points) to 5-20 mm away.
  const Centerline centerline = buildCenterline(spec.vessels);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, centerline.numPoints() - 1);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> reach(0.005, 0.02);
  std::vector<std::pair<Vec3, Vec3>> segments;
  while (segments.size() < 2000) {
    const Vec3 a = centerline.position[pick(rng)];
    const Vec3 dir = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Vec3 b = a + reach(rng) * dir;
    if (field.evaluate(a, 0.0).value > 0.0 && field.evaluate(b, 0.0).value < 0.0)
      segments.emplace_back(a, b);
  }
  RootOptions fine;
  fine.tolerance = 1e-13;
  std::vector<Vec3> reference;
  for (const auto& [a, b] : segments)
    reference.push_back(firstRoot(field, a, b, 0.0, {}, fine).point);
  std::vector<Row> rows;
  for (double tol : {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11}) {
    RootOptions o;
    o.tolerance = tol;
    double error = 0.0, best_s = 1e300;
    for (int repeat = 0; repeat < 5; ++repeat) {  // the fastest of 5 passes
      const auto t0 = Clock::now();
      for (size_t i = 0; i < segments.size(); ++i) {
        const SurfacePoint p = firstRoot(field, segments[i].first, segments[i].second, 0.0, {}, o);
        error = std::max(error, (p.point - reference[i]).norm());
      }
      best_s = std::min(best_s, secondsSince(t0));
    }
    Row r;
    r.knob = "root_tolerance";
    std::ostringstream v;
    v << tol;
    r.setting = v.str();
    r.cost = 1e6 * best_s / segments.size();
    r.cost_unit = "us_per_query";
    r.error_m = error;
    std::cerr << "  tolerance " << tol << " m: " << r.cost << " us per query, largest error "
              << error << " m\n";
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

int accuracyCommand(const std::string& what, double duration, const std::string& csv) {
  const std::vector<Row> rows = what == "beam"   ? sweepBeam()
                                : what == "root" ? sweepRoot()
                                                 : sweepScene(what, duration);
  if (csv.empty()) {
    writeRows(rows, std::cout);
    return 0;
  }
  std::ofstream out(csv);
  writeRows(rows, out);
  if (!out) {
    std::cerr << "evsim: cannot write " << csv << "\n";
    return kExitFailure;
  }
  std::cerr << "wrote " << csv << "\n";
  return 0;
}

}  // namespace evsim
