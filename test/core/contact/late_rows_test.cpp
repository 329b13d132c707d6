// StepStats::first_rows and late_rows: the rows of the first activation
// loop's LCP, and the rows each later loop found, by kind. Two counts made
// in different places (the LCP's size at each loop, the step's contacts
// tallied by kind after the loop) must agree: the last LCP holds the first
// loop's rows and the late ones. A step of one loop found nothing late; a
// scene without device pairs or a coaxial device has no late rows of
// those kinds.
#include <gtest/gtest.h>

#include <cstdio>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

struct LateTally {
  int steps{0};
  int extra_loops{0};
  LateRows late;
};

// Steps the scene from `from_step` on for `steps` steps, checking each
// unsubdivided step's rows: last LCP = first loop's + late ones.
LateTally stepAndCheck(const char* scene, int from_step, int steps) {
  const SceneModel model = loadScene(scene);
  SimData d = makeData(model);
  for (int k = 0; k < from_step; ++k) EXPECT_EQ(step(model, &d), StepStatus::kOk) << d.last_error;
  LateTally tally;
  for (int k = 0; k < steps; ++k) {
    EXPECT_EQ(step(model, &d), StepStatus::kOk) << d.last_error;
    const ContactStats& s = d.stats.contact;
    if (d.stats.subdivisions > 0 || d.stats.asleep || s.activation_loops == 0) continue;
    const LateRows& late = s.late_rows;
    EXPECT_EQ(s.contacts, s.first_rows + late.wall + late.pair + late.lumen)
        << scene << " step " << d.step;
    if (s.activation_loops == 1) {
      EXPECT_EQ(late.wall + late.pair + late.lumen, 0) << scene << " step " << d.step;
    }
    ++tally.steps;
    tally.extra_loops += s.activation_loops - 1;
    tally.late += late;
  }
  std::printf(
      "[ metric   ] %s, %d steps from step %d: %d loops after the first; late rows: "
      "%d wall, %d pair, %d lumen\n",
      scene, tally.steps, from_step, tally.extra_loops, tally.late.wall, tally.late.pair,
      tally.late.lumen);
  return tally;
}

// The coil in the dome (t = 11 s, where its turns spring across it): its
// self-contacts and the dome's wall are both found late (the pairs that
// held it in the last step start each step, so most steps find none).
TEST(LateRows, TheCoilFindsItsOwnTurnsAndTheWallLate) {
  const LateTally t = stepAndCheck("aneurysm", 11000, 300);
  EXPECT_GT(t.extra_loops, 0);
  EXPECT_GT(t.late.pair, 0);
  EXPECT_GT(t.late.wall, 0);
  EXPECT_EQ(t.late.lumen, 0);
}

// The carotid wire reaching the arch: only wall planes.
TEST(LateRows, AWireAloneFindsOnlyWallPlanesLate) {
  const LateTally t = stepAndCheck("carotid", 4000, 1500);
  EXPECT_GT(t.late.wall, 0);
  EXPECT_EQ(t.late.pair, 0);
  EXPECT_EQ(t.late.lumen, 0);
}

}  // namespace
}  // namespace evsim
