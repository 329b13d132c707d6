// Coulomb friction solvers on the friction problems of `carotid_catheter`
// (a guidewire in a catheter; wall and lumen contacts, ~36 candidates of
// which ~5 carry a force, many redundant): our Newton solver (the status
// method extended to stick and slip), our NSGS, and Siconos' NSN_AC, each
// from zero forces to a residual of 1e-10. One iteration solves the whole
// set; the counter `per_problem` is the time per problem [s].
#include <benchmark/benchmark.h>

#include <vector>

#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/contact/friction.h"
#include "endovascular_sim/sim/simulation.h"
#include "siconos_oracle.h"

namespace evsim {
namespace {

/// The last friction problem of every 6th of the scene's first 600 steps.
const std::vector<LcpRecord>& sceneFrictionProblems() {
  static std::vector<LcpRecord> problems;
  if (problems.empty()) {
    const SceneModel m = loadScene("carotid_catheter");
    SimData d = makeData(m);
    d.record_lcp = true;
    for (int k = 0; k < 600 && step(m, &d) == StepStatus::kOk; ++k)
      if (k % 6 == 0 && d.lcp.mu.size() > 0) problems.push_back(d.lcp);
  }
  return problems;
}

void report(benchmark::State& st, const std::vector<LcpRecord>& problems,
            const std::vector<VecX>& forces, int unsolved, long steps) {
  double worst = 0.0;
  for (size_t k = 0; k < problems.size(); ++k)
    worst =
        std::max(worst, frictionResidual(problems[k].W, problems[k].q, problems[k].mu, forces[k]));
  const double count = static_cast<double>(problems.size());
  st.counters["problems"] = count;
  st.counters["per_problem"] = benchmark::Counter(
      count, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["worst_residual"] = worst;
  st.counters["unsolved"] = unsolved;
  if (steps >= 0) st.counters["steps_per_problem"] = steps / count;
}

void runOurs(benchmark::State& st, FrictionSolver solver) {
  const std::vector<LcpRecord>& problems = sceneFrictionProblems();
  std::vector<VecX> forces(problems.size());
  FrictionOptions o;
  o.solver = solver;
  o.max_sweeps = 20000;
  int unsolved = 0;
  long steps = 0;
  for (auto _ : st) {
    unsolved = 0;
    steps = 0;
    for (size_t k = 0; k < problems.size(); ++k) {
      forces[k].resize(0);  // from zero
      FrictionStats fs;
      const LcpRecord& p = problems[k];
      if (solveFrictionalContact(p.W, p.q, p.mu, o, &forces[k], &fs) != LcpStatus::kSolved)
        ++unsolved;
      steps += fs.sweeps;
    }
  }
  report(st, problems, forces, unsolved, steps);
}

void BM_FrictionNewton(benchmark::State& st) { runOurs(st, FrictionSolver::kNewton); }
void BM_FrictionNsgs(benchmark::State& st) { runOurs(st, FrictionSolver::kNsgs); }

void BM_FrictionSiconosNsnAc(benchmark::State& st) {
  const std::vector<LcpRecord>& problems = sceneFrictionProblems();
  std::vector<VecX> forces(problems.size());
  int unsolved = 0;
  for (auto _ : st) {
    unsolved = 0;
    for (size_t k = 0; k < problems.size(); ++k) {
      const LcpRecord& p = problems[k];
      if (test::siconosFrictionContact(p.W, p.q, p.mu, SICONOS_FRICTION_3D_NSN_AC, 1e-10,
                                       &forces[k], 20000) != 0)
        ++unsolved;
    }
  }
  report(st, problems, forces, unsolved, -1);
}

BENCHMARK(BM_FrictionNewton)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrictionNsgs)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrictionSiconosNsnAc)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace evsim
