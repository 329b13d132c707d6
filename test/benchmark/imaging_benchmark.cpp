// Virtual fluoroscopy: one frame of the carotid scene with the wire deep in
// the vessels (after its 6 s script) at 256, 512 and 1024 pixels a side;
// the live frame (body cached, devices, detector) and a frame during an
// angiogram (the lumen traced once per C-arm pose, then its contrast
// levels each frame), and the trace of the lumen itself. The clinical
// rates need a frame within 133, 67 or 33 ms (7.5, 15, 30 frames/s).
#include <benchmark/benchmark.h>

#include <map>

#include "endovascular_sim/imaging/detector.h"
#include "endovascular_sim/imaging/xray_renderer.h"

namespace evsim {
namespace {

struct Carotid {
  SceneModel model;
  SimData data;
};

const Carotid& carotidDeepIn() {
  static const Carotid* scene = [] {
    auto* c = new Carotid{loadScene("carotid"), {}};
    c->data = makeData(c->model);
    bool recovered = false;
    for (int k = 0; k < 6000; ++k) stepOrRecover(c->model, &c->data, &recovered);
    return c;
  }();
  return *scene;
}

XraySpec specOf(int pixels) {
  XraySpec spec;
  spec.c_arm.pixels = pixels;
  return spec;
}

/// Frames as the node makes them: the line integrals, then the display.
void renderFrames(benchmark::State& st, XrayRenderer* renderer, const SimData& data) {
  XrayFrame frame;
  long index = 0;
  for (auto _ : st) {
    renderer->render(data, &frame);
    const auto gray = detectorGray(frame, renderer->spec(), renderer->referenceAttenuation(),
                                   index++, nullptr, &renderer->bodyAttenuation());
    benchmark::DoNotOptimize(gray.data());
  }
}

void BM_XrayLiveFrame(benchmark::State& st) {
  const Carotid& c = carotidDeepIn();
  XrayRenderer renderer(c.model, specOf(static_cast<int>(st.range(0))));
  renderFrames(st, &renderer, c.data);
}
BENCHMARK(BM_XrayLiveFrame)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);

void BM_XrayAngiogramFrame(benchmark::State& st) {
  const Carotid& c = carotidDeepIn();
  XrayRenderer renderer(c.model, specOf(static_cast<int>(st.range(0))));
  renderer.injectContrast(c.model.atlas->pointAt(0, 0.0), c.data.time, 10.0);  // the whole tree
  XrayFrame traced;
  renderer.render(c.data, &traced);  // the lumen traced for this pose
  renderFrames(st, &renderer, c.data);
}
BENCHMARK(BM_XrayAngiogramFrame)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);

void BM_XrayLumenTrace(benchmark::State& st) {
  const Carotid& c = carotidDeepIn();
  XrayRenderer renderer(c.model, specOf(static_cast<int>(st.range(0))));
  VesselProjection lumen;
  for (auto _ : st) {
    lumen.build(*c.model.vessels, *c.model.centerline, c.model.aneurysms, renderer.camera(), 1);
    benchmark::DoNotOptimize(lumen.numPieces());
  }
  st.counters["field_evaluations"] = static_cast<double>(lumen.fieldEvaluations());
}
BENCHMARK(BM_XrayLumenTrace)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace evsim
