// Assembly + chain factorisation (block LDL^T) + one solve of the free motion of a
// guidewire-like device, for 50 ... 400 elements. Cost should grow linearly.
#include <benchmark/benchmark.h>

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/implicit_euler.h"

namespace evsim {
namespace {

BeamSection nitinolWire() {
  BeamSection s;
  s.young_modulus = 60e9;
  s.shear_modulus = 60e9 / 2.66;
  s.outer_radius = 1.78e-4;
  s.density = 6450.0;
  return s;
}

void BM_FreeMotionStep(benchmark::State& st) {
  const int elements = static_cast<int>(st.range(0));
  const DeviceModel model =
      buildDeviceModel(straightDeviceSpec("wire", nitinolWire(), 0.002 * elements, elements));
  Introducer intro;
  DeviceState state = placeDevice(model, intro, model.length - 0.001, 0.0);
  // A bent configuration so that the co-rotational terms are non-trivial.
  for (int i = 0; i < model.num_nodes; ++i) state.position[i].y() += 1e-4 * std::sin(0.1 * i);
  DeviceWorkspace ws;
  const Vec3 gravity(0, 0, -9.81);
  computeFreeMotion(model, intro, gravity, 1e-3, state, &ws);  // symbolic analysis once
  for (auto _ : st) {
    computeFreeMotion(model, intro, gravity, 1e-3, state, &ws);
    benchmark::DoNotOptimize(ws.dq.data());
  }
  st.counters["elements"] = elements;
  st.SetComplexityN(elements);
}
BENCHMARK(BM_FreeMotionStep)
    ->Arg(50)
    ->Arg(100)
    ->Arg(200)
    ->Arg(400)
    ->Complexity(benchmark::oN)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace evsim

BENCHMARK_MAIN();
