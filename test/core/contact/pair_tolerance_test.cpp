// contact.pair_tolerance: how far two device surfaces may overlap at the end
// of a step before the activation loop goes on (docs/performance.md, "What
// accuracy costs"). Checked by brute force over the coil's elements.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "self_overlap_check.h"

namespace evsim {
namespace {

struct PackedRun {
  double deepest{-1.0};  // overlap of two coil elements after any step [m]
  long loops{0};         // activation loops over the run
  long rows{0};          // rows of the steps' last LCPs, summed
  int max_rows{0};
  long steps{0};
};

/// aneurysm_packed's first 3 s (its coil's turns meet from about 2.3 s) with
/// the given pair tolerance (and new_pair_overlap [m], else the scene's);
/// the deepest overlap checked after every step.
PackedRun runPacked(double pair_tolerance, std::optional<double> new_pair_overlap = {}) {
  SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm_packed"));
  spec.contact.pair_tolerance = pair_tolerance;
  if (new_pair_overlap) spec.contact.new_pair_overlap = *new_pair_overlap;
  const SceneModel model = buildSceneModel(spec);
  SimData data = makeData(model);
  PackedRun run;
  for (; run.steps < 3000; ++run.steps) {
    if (step(model, &data) != StepStatus::kOk) {
      ADD_FAILURE() << "step " << run.steps + 1 << ": " << data.last_error;
      break;
    }
    run.loops += data.stats.contact.activation_loops;
    run.rows += data.stats.contact.contacts;
    run.max_rows = std::max(run.max_rows, data.stats.contact.contacts);
    run.deepest =
        std::max(run.deepest, test::deepestSelfOverlap(model.devices.back(), data.devices.back()));
  }
  return run;
}

TEST(PairTolerance, TheCoilsTurnsOverlapByAtMostTheTolerance) {
  const double wall = ContactOptions{}.penetration_tolerance;  // the scene's: the default
  const PackedRun plain = runPacked(0.0);                      // pairs held to the wall's 1 um
  const PackedRun loose = runPacked(5e-6);
  ASSERT_EQ(plain.steps, 3000);
  ASSERT_EQ(loose.steps, 3000);
  EXPECT_LE(plain.deepest, wall + 1e-9);
  EXPECT_LE(loose.deepest, 5e-6 + 1e-9);
  // The tolerance is used: turns end deeper than the wall's tolerance, and
  // the loop stops sooner.
  EXPECT_GT(loose.deepest, wall);
  EXPECT_LT(loose.loops, plain.loops);
  std::printf(
      "[ metric   ] aneurysm_packed, 3 s: deepest overlap of two coil elements %.3f um with pairs "
      "at the wall's 1 um, %.3f um at 5 um; activation loops %ld -> %ld\n",
      plain.deepest * 1e6, loose.deepest * 1e6, plain.loops, loose.loops);
}

// contact.new_pair_overlap: a pair that held no force in the last step
// becomes a row in the first detection once it overlaps by more than this,
// not once it touches. The turns still end every step within the pair
// tolerance (brute force), with fewer rows.
TEST(PairTolerance, NewPairsFromAnOverlapEndWithinTheToleranceOnFewerRows) {
  const PackedRun touching = runPacked(5e-6, 0.0);
  const PackedRun beyond = runPacked(5e-6, 2.5e-6);
  ASSERT_EQ(touching.steps, 3000);
  ASSERT_EQ(beyond.steps, 3000);
  EXPECT_LE(touching.deepest, 5e-6 + 1e-9);
  EXPECT_LE(beyond.deepest, 5e-6 + 1e-9);
  EXPECT_LT(beyond.rows, touching.rows);
  std::printf(
      "[ metric   ] aneurysm_packed, 3 s, pair tolerance 5 um: new pairs from touching -> from "
      "2.5 um: deepest overlap %.3f -> %.3f um, LCP rows %ld -> %ld (at most %d -> %d), "
      "activation loops %ld -> %ld\n",
      touching.deepest * 1e6, beyond.deepest * 1e6, touching.rows, beyond.rows, touching.max_rows,
      beyond.max_rows, touching.loops, beyond.loops);
}

}  // namespace
}  // namespace evsim
