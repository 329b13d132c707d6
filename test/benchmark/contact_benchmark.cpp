// The contact space at c = 10 ... 400 contacts on a 200-element guidewire:
//  - the Delassus operator W = H A^-1 H^T from the band of A^-1 (the contact
//    solver's), from one block solve, and from c separate solves (naive);
//  - LCP solvers on those W: the status method, PGS, Lemke, and Siconos'
//    Lemke and pivoting solvers (its Newton-min needed seconds at c = 10 on
//    these nearly dependent contacts and is left out).
// Counters: c and the natural-map residual reached.
#include <benchmark/benchmark.h>

#include <map>
#include <random>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/contact/delassus.h"
#include "endovascular_sim/contact/lcp.h"
#include "endovascular_sim/mechanics/implicit_euler.h"
#include "endovascular_sim/sim/simulation.h"
#include "siconos_oracle.h"

namespace evsim {
namespace {

struct ContactSpace {
  DeviceModel model;
  DeviceState state;
  DeviceWorkspace ws;
  std::vector<ContactRow> rows;
  MatX Ht;  // free DOFs x c (dense, for the naive way)
  MatX W;
  VecX q;
};

/// c contacts at random points of a bent nitinol wire (200 elements unless
/// told), normals across the wire, penetrations up to 50 um (a third of them
/// separating).
ContactSpace& space(int c, int elements = 200) {
  static std::map<std::pair<int, int>, ContactSpace> cache;
  auto it = cache.find({c, elements});
  if (it != cache.end()) return it->second;
  ContactSpace& s = cache[{c, elements}];
  BeamSection sec;
  sec.young_modulus = 60e9;
  sec.shear_modulus = 60e9 / 2.66;
  sec.outer_radius = 1.78e-4;
  sec.density = 6450;
  s.model = buildDeviceModel(straightDeviceSpec("wire", sec, 0.002 * elements, elements));
  Introducer intro;
  s.state = placeDevice(s.model, intro, s.model.length - 0.002, 0.0);
  for (int i = 0; i < s.model.num_nodes; ++i) s.state.position[i].y() += 0.01 * std::sin(0.03 * i);
  computeFreeMotion(s.model, intro, Vec3::Zero(), 1e-3, s.state, &s.ws);
  std::mt19937 rng(c);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int first = s.ws.first_free_node, n = s.ws.factor.size();
  s.Ht = MatX::Zero(n, c);
  s.q.resize(c);
  for (int j = 0; j < c; ++j) {
    const SamplePoint p{first + static_cast<int>(u(rng) * (s.model.num_nodes - 2 - first)), u(rng),
                        1.78e-4};
    const Vec3 t = s.state.rotation[p.element] * Vec3::UnitX();
    const Vec3 n_dir = t.unitOrthogonal();
    const double a = 2 * M_PI * u(rng);
    const Vec3 normal = Eigen::AngleAxisd(a, t) * n_dir;
    const Row12 row = contactRow(s.model, s.state, p, normal);
    ContactRow cr;
    cr.offset[0] = 6 * (p.element - first);
    cr.h[0] = row;
    s.rows.push_back(cr);
    for (int half = 0; half < 2; ++half)
      s.Ht.col(j).segment<6>(6 * (p.element + half - first)) = row.segment<6>(6 * half).transpose();
    s.q(j) = u(rng) < 0.33 ? 1e-5 * u(rng) : -5e-5 * u(rng);
  }
  MatX Y;
  delassusOperator(s.ws.factor, s.rows, &Y, &s.W);
  return s;
}

/// W from the block solve into *Y: Y over the whole chain (MatX), or over
/// the rows' trailing blocks only (TrailingSolve, the contact solver's).
template <typename Solved>
void timeBlockSolve(benchmark::State& st, Solved* Y) {
  ContactSpace& s = space(static_cast<int>(st.range(0)));
  MatX W;
  for (auto _ : st) {
    delassusOperator(s.ws.factor, s.rows, Y, &W);
    benchmark::DoNotOptimize(W.data());
  }
  st.counters["c"] = static_cast<double>(st.range(0));
}

void BM_DelassusBlockSolve(benchmark::State& st) {
  MatX Y;
  timeBlockSolve(st, &Y);
}

/// The contact solver's way: the band of A^-1 (its cost included) and the
/// columns carried down the chain.
void BM_DelassusChain(benchmark::State& st) {
  ContactSpace& s = space(static_cast<int>(st.range(0)));
  ChainInverse inverse;
  MatX W;
  for (auto _ : st) {
    inverse.compute(s.ws.system, s.ws.first_free_node);
    chainDelassusOperator(inverse, s.rows, &W);
    benchmark::DoNotOptimize(W.data());
  }
  st.counters["c"] = static_cast<double>(st.range(0));
  st.counters["difference"] = (W - s.W).norm() / s.W.norm();  // to the block solve's
}

/// The band of A^-1 from the chain's factor alone (ChainInverse::computeFrom,
/// as a loop that switches to the band pays it), on the 200-element wire.
void BM_DelassusBandFromFactor(benchmark::State& st) {
  ContactSpace& s = space(static_cast<int>(st.range(0)));
  ChainInverse inverse;
  for (auto _ : st) {
    inverse.computeFrom(s.ws.factor);
    benchmark::DoNotOptimize(&inverse);
  }
}

/// The sweep alone, the band given (a later loop of the step with the same
/// matrix): W from c rows.
void BM_DelassusSweep(benchmark::State& st) {
  ContactSpace& s = space(static_cast<int>(st.range(0)));
  ChainInverse inverse;
  inverse.computeFrom(s.ws.factor);
  MatX W;
  for (auto _ : st) {
    chainDelassusOperator(inverse, s.rows, &W);
    benchmark::DoNotOptimize(W.data());
  }
  st.counters["c"] = static_cast<double>(st.range(0));
}

/// The block solve over the rows' trailing blocks only (c rows at random
/// points of the wire).
void BM_DelassusTrailingSolve(benchmark::State& st) {
  TrailingSolve Y;
  timeBlockSolve(st, &Y);
  st.counters["first_block"] = Y.first_block;
}

/// A loop's update of W on a 625-element chain (the packed coil's) with c
/// rows (range(0)), the last f of them fresh (range(1)), by either path
/// (range(2): 0 the fresh columns alone, 1 one sweep, 2 the automatic
/// choice): where the automatic choice should switch.
void BM_DelassusUpdate(benchmark::State& st) {
  const int c = static_cast<int>(st.range(0)), fresh = static_cast<int>(st.range(1));
  ContactSpace& s = space(c, 625);
  const DelassusUpdate path = st.range(2) == 0   ? DelassusUpdate::kFreshColumns
                              : st.range(2) == 1 ? DelassusUpdate::kSweep
                                                 : DelassusUpdate::kAutomatic;
  ChainInverse inverse;
  inverse.compute(s.ws.system, s.ws.first_free_node);
  MatX full;
  chainDelassusOperator(inverse, s.rows, &full);
  DelassusBuffer W;  // as in the contact solver: the capacity is there
  W.storage = full;
  for (auto _ : st) {
    W.size = c - fresh;  // the kept block holds its final entries
    updateChainDelassusOperator(inverse, s.rows, std::vector<char>(), &W, path);
    benchmark::DoNotOptimize(W.storage.data());
  }
  st.counters["fresh"] = fresh;
  st.counters["difference"] = (W.view() - full).norm() / full.norm();
}

void BM_DelassusSeparateSolves(benchmark::State& st) {
  ContactSpace& s = space(static_cast<int>(st.range(0)));
  const int c = static_cast<int>(st.range(0));
  MatX Y(s.Ht.rows(), c), W;
  for (auto _ : st) {
    for (int j = 0; j < c; ++j) {
      VecX col = s.Ht.col(j);
      s.ws.factor.solveInPlace(&col);
      Y.col(j) = col;
    }
    W.noalias() = s.Ht.transpose() * Y;
    benchmark::DoNotOptimize(W.data());
  }
  st.counters["c"] = c;
}

/// Times one of our solvers on (W, q). Counters: c, forces, pivots or
/// sweeps, and the residual recomputed from z.
void timeOurs(benchmark::State& st, const MatX& W, const VecX& q, const LcpOptions& o) {
  VecX z;
  LcpStats ls;
  for (auto _ : st) {
    z.resize(0);  // every solve from cold (a z of size c would be its warm start)
    solveLcp(W, q, o, &z, &ls);
    benchmark::DoNotOptimize(z.data());
  }
  st.counters["c"] = static_cast<double>(q.size());
  st.counters["active"] = static_cast<double>((z.array() > 0.0).count());
  st.counters["iterations"] = ls.iterations;
  st.counters["residual"] = lcpResidual(W, q, z);
}

/// Times a Siconos LCP solver on (W, q) at 1e-12.
void timeSiconos(benchmark::State& st, const MatX& W, const VecX& q, int solver) {
  VecX z;
  int info = 0;
  for (auto _ : st) {
    info = test::siconosLcp(W, q, solver, 1e-12, &z, 100000);
    benchmark::DoNotOptimize(z.data());
  }
  st.counters["c"] = static_cast<double>(q.size());
  st.counters["residual"] = lcpResidual(W, q, z);
  st.counters["info"] = info;
}

void runOurs(benchmark::State& st, LcpSolver solver, int max_iterations) {
  const ContactSpace& s = space(static_cast<int>(st.range(0)));
  LcpOptions o;
  o.solver = solver;
  o.max_iterations = max_iterations;
  timeOurs(st, s.W, s.q, o);
}

void BM_StatusMethod(benchmark::State& st) { runOurs(st, LcpSolver::kStatusMethod, 0); }
void BM_Lemke(benchmark::State& st) { runOurs(st, LcpSolver::kLemke, 0); }
void BM_Pgs100(benchmark::State& st) { runOurs(st, LcpSolver::kPgs, 100); }
void BM_Pgs1000(benchmark::State& st) { runOurs(st, LcpSolver::kPgs, 1000); }

void runSiconos(benchmark::State& st, int solver) {
  const ContactSpace& s = space(static_cast<int>(st.range(0)));
  timeSiconos(st, s.W, s.q, solver);
}

void BM_SiconosLemke(benchmark::State& st) { runSiconos(st, SICONOS_LCP_LEMKE); }
void BM_SiconosPivot(benchmark::State& st) { runSiconos(st, SICONOS_LCP_PIVOT); }

/// LCPs dumped from real steps: the `aneurysm` scene (the coil deployed
/// with self-contact, 6,000 steps), `dead_end` (a wire buckling in a
/// closed tube, 2,500 steps) and `large_step` (40 ms steps, the wire looped
/// in the arch, 200 steps: the LCPs of 300-500 rows). For each target size
/// the step whose last LCP has the nearest number of rows (the counter `c`
/// says which).
const LcpRecord& sceneLcp(int target) {
  static std::map<int, LcpRecord> best;
  if (best.empty()) {
    for (const auto& [scene, steps] :
         {std::pair{"aneurysm", 6000}, std::pair{"dead_end", 2500}, std::pair{"large_step", 200}}) {
      const SceneModel m = loadScene(scene);
      SimData d = makeData(m);
      d.record_lcp = true;
      for (int k = 0; k < steps; ++k) {
        if (step(m, &d) != StepStatus::kOk) break;
        const int c = static_cast<int>(d.lcp.q.size());
        for (int t : {10, 50, 100, 200, 250, 300, 400}) {
          auto it = best.find(t);
          if (c > 0 && (it == best.end() || std::abs(c - t) < std::abs(it->second.q.size() - t)))
            best[t] = d.lcp;
        }
      }
    }
  }
  return best[target];
}

void runOursOnScene(benchmark::State& st, LcpSolver solver, bool start_from_violated = false) {
  const LcpRecord& r = sceneLcp(static_cast<int>(st.range(0)));
  LcpOptions o;
  o.solver = solver;
  o.start_from_violated = start_from_violated;
  timeOurs(st, r.W, r.q, o);
}

void runSiconosOnScene(benchmark::State& st, int solver) {
  const LcpRecord& r = sceneLcp(static_cast<int>(st.range(0)));
  timeSiconos(st, r.W, r.q, solver);
}

void BM_SceneStatusMethod(benchmark::State& st) { runOursOnScene(st, LcpSolver::kStatusMethod); }
void BM_SceneStatusMethodPaperStart(benchmark::State& st) {
  runOursOnScene(st, LcpSolver::kStatusMethod, true);
}
void BM_SceneLemke(benchmark::State& st) { runOursOnScene(st, LcpSolver::kLemke); }
void BM_SceneSiconosLemke(benchmark::State& st) { runSiconosOnScene(st, SICONOS_LCP_LEMKE); }
void BM_SceneSiconosPivot(benchmark::State& st) { runSiconosOnScene(st, SICONOS_LCP_PIVOT); }

#define SCENE_SIZES                                                           \
  ->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Arg(250)->Arg(300)->Arg(400)->Unit( \
      benchmark::kMicrosecond)
BENCHMARK(BM_SceneStatusMethod) SCENE_SIZES;
BENCHMARK(BM_SceneStatusMethodPaperStart) SCENE_SIZES;
BENCHMARK(BM_SceneLemke) SCENE_SIZES;
BENCHMARK(BM_SceneSiconosLemke) SCENE_SIZES;
BENCHMARK(BM_SceneSiconosPivot) SCENE_SIZES;

#define CONTACT_SIZES \
  ->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Arg(400)->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_DelassusChain) CONTACT_SIZES;
BENCHMARK(BM_DelassusBlockSolve) CONTACT_SIZES;
#define FEW_CONTACTS ->Arg(2)->Arg(5)->Arg(10)->Arg(20)->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_DelassusBandFromFactor)->Arg(2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DelassusSweep) FEW_CONTACTS;
BENCHMARK(BM_DelassusTrailingSolve) FEW_CONTACTS;
BENCHMARK(BM_DelassusUpdate)
    ->ArgsProduct({{100, 300, 500}, {1, 5, 10, 20, 40, 80}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DelassusSeparateSolves) CONTACT_SIZES;
BENCHMARK(BM_StatusMethod) CONTACT_SIZES;
BENCHMARK(BM_Lemke) CONTACT_SIZES;
BENCHMARK(BM_Pgs100) CONTACT_SIZES;
BENCHMARK(BM_Pgs1000) CONTACT_SIZES;
BENCHMARK(BM_SiconosLemke) CONTACT_SIZES;
BENCHMARK(BM_SiconosPivot) CONTACT_SIZES;

}  // namespace
}  // namespace evsim
