// The vessel field at the scale of a cerebrovascular network: one field +
// gradient evaluation and one first-root query near the right common carotid
// wall, for networks of 10 ... 16,000 generated vessels; and the time to
// build (grow + index) the scene's 4,000-vessel network; and the fidelity of
// each shipped tree's surface to its radii (counters: the lumen radius
// against the centreline's, along the vessels and at forks and ends, in %;
// the test trees print theirs in CenterlineVtk.* and PatientExample.*).
#include <benchmark/benchmark.h>

#include <map>
#include <random>

#include "endovascular_sim/geometry/network_generator.h"
#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/geometry/surface_fidelity.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {
namespace {

Centerline carotid() { return loadCenterlineFile(configDirectory() + "/vessels/carotid.swc"); }

const VesselField& networkOf(int vessels) {
  static std::map<int, VesselField> cache;
  auto it = cache.find(vessels);
  if (it == cache.end()) {
    Centerline c = carotid();
    NetworkOptions o;
    o.vessels = vessels;
    o.min_radius = 0.05e-3;
    o.growth_box = Eigen::AlignedBox3d(Vec3(-0.2, -0.15, 0.15), Vec3(0.2, 0.2, 0.45));
    growNetwork(o, &c);
    it = cache.emplace(vessels, VesselField(c, {}, {}, {})).first;
  }
  return it->second;
}

/// Points inside the right common carotid, near its wall (where contacts are).
std::vector<Vec3> queryPoints() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> pts;
  for (int k = 0; k < 256; ++k) {
    const double z = 0.105 + 0.03 * u(rng);
    const Vec3 axis(-0.031 - 0.00005 * (z - 0.105) * 1e3, 0.017, z);
    const Vec3 radial = Vec3(u(rng), u(rng), 0.0).normalized();
    pts.push_back(axis + 0.0030 * radial);
  }
  return pts;
}

void BM_FieldAndGradient(benchmark::State& st) {
  const VesselField& f = networkOf(static_cast<int>(st.range(0)));
  const std::vector<Vec3> pts = queryPoints();
  size_t k = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(f.evaluate(pts[k++ & 255], 1.78e-4));
  }
  st.counters["segments"] = f.numSegments();
  st.counters["primitives_in_cell"] = f.primitivesNear(pts[0]);
}
BENCHMARK(BM_FieldAndGradient)
    ->Arg(10)
    ->Arg(100)
    ->Arg(1000)
    ->Arg(4000)
    ->Arg(16000)
    ->Unit(benchmark::kNanosecond);

void BM_FirstRootQuery(benchmark::State& st) {
  const VesselField& f = networkOf(static_cast<int>(st.range(0)));
  const std::vector<Vec3> pts = queryPoints();
  // A node near the wall moving 0.5 mm outward (a hit) or along the wall.
  size_t k = 0;
  for (auto _ : st) {
    const Vec3& p = pts[k++ & 255];
    const Vec3 out = Vec3(p.x() + 0.031, p.y() - 0.017, 0.0).normalized();
    benchmark::DoNotOptimize(firstRoot(f, p, p + 5e-4 * out, 1.78e-4));
  }
}
BENCHMARK(BM_FirstRootQuery)->Arg(10)->Arg(4000)->Arg(16000)->Unit(benchmark::kNanosecond);

void BM_BuildNetworkScene(benchmark::State& st) {
  const SceneSpec spec = loadSceneFile(configDirectory() + "/scenes/network.yaml");
  for (auto _ : st) {
    const VesselField f = buildVesselField(spec.vessels, true);
    benchmark::DoNotOptimize(f.numSegments());
  }
}
BENCHMARK(BM_BuildNetworkScene)->Unit(benchmark::kMillisecond);

void surfaceFidelity(benchmark::State& st, const char* scene) {
  const SceneSpec spec = loadSceneFile(resolveScenePath(scene));
  const Centerline c = buildCenterline(spec.vessels);
  const VesselField field(c, {}, {}, spec.vessels.field);  // the tree's own surface: no domes
  SurfaceFidelity f;
  for (auto _ : st) f = measureSurfaceFidelity(field, c);
  st.counters["along_median_pct"] = 100.0 * f.along.median;
  st.counters["along_worst_pct"] = 100.0 * f.along.worst;
  st.counters["forks_median_pct"] = 100.0 * f.at_forks.median;
  st.counters["rays"] = f.along.rays + f.at_forks.rays;
}
BENCHMARK_CAPTURE(surfaceFidelity, carotid, "carotid")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(surfaceFidelity, aneurysm, "aneurysm")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(surfaceFidelity, tortuous, "tortuous")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(surfaceFidelity, dead_end, "dead_end")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(surfaceFidelity, patient_example, "patient_example")
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace evsim
