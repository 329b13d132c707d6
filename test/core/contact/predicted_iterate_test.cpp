// contact.predict_first_iterate: the first activation loop detects and is
// linearised at x_f moved by the last step's contact forces. Its answers
// must obey Signorini's law as the loop from x_f does (an active contact
// touches its plane, none is beyond it), in fewer loops where the free
// motion swings far from where the contacts hold a device; at rest the
// prediction is the answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "endovascular_sim/sim/simulation.h"
#include "signorini_check.h"

namespace evsim {
namespace {

using test::largestActiveGap;
using test::largestNodeDistance;

// The coil of `aneurysm` pressed into the dome springs half a millimetre
// open in its free motion; started where the last step's forces hold it,
// the loop finds the turns that touch in its first pass. Each step from
// the same state both ways, the run going on from x_f's answer: both obey
// Signorini's law to the penetration tolerance, and the predicted steps
// take fewer loops.
TEST(PredictedFirstIterate, TheCoilsStepsObeySignoriniInFewerLoops) {
  SceneModel from_free = loadScene("aneurysm");
  from_free.contact.predict_first_iterate = false;
  SceneModel predicted = from_free;
  predicted.contact.predict_first_iterate = true;
  const double tol = from_free.contact.penetration_tolerance;
  test::BothWays t;  // a: from x_f, b: predicted
  ASSERT_NO_FATAL_FAILURE(test::stepBothWays(from_free, predicted, 6000, 300,
                                             [&](int k, const SimData& d, const SimData& other) {
                                               test::expectWithinTolerance(other, tol, k);
                                               t.add(d, other);
                                             }));
  std::printf(
      "[ metric   ] aneurysm t = 6-6.3 s: loops %ld from x_f, %ld predicted; largest |gap| of an "
      "active contact %.3g m from x_f, %.3g m predicted; answers %.3g m apart at most\n",
      t.loops_a, t.loops_b, t.gap_a, t.gap_b, t.apart);
  EXPECT_LE(t.gap_b, tol);
  EXPECT_LE(t.gap_a, tol);
  EXPECT_LT(t.loops_b, t.loops_a);
}

// The carotid wire fully inserted and at rest (t = 11 s, sleep off): the
// last step's forces hold it, so the predicted iterate is the answer and
// one loop confirms it each step. Linearised there, its active contacts
// touch their planes (the loop from x_f, linearised millimetres away,
// leaves them a fraction of a micrometre off, inside the tolerance): the
// first predicted step moves the wire by 3 um to that rest, and the
// damping settles it there within 300 steps, as far as the same steps
// without the prediction do.
TEST(PredictedFirstIterate, AWireAtRestIsWhereItsForcesHoldIt) {
  SceneModel m = loadScene("carotid");
  m.sleep.enabled = false;
  SimData d = makeData(m);
  for (int k = 0; k < 11000; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  const double gap_free = largestActiveGap(d);
  // The same steps without the prediction: how far the wire still settles.
  const SceneModel m_free = m;
  SimData d_free = d;
  m.contact.predict_first_iterate = true;
  double gap_predicted = 0.0, moved = 0.0, moved_free = 0.0;
  for (int k = 0; k < 400; ++k) {
    const std::vector<DeviceState> before = d.devices, before_free = d_free.devices;
    ASSERT_EQ(step(m, &d), StepStatus::kOk) << "step " << k << ": " << d.last_error;
    ASSERT_EQ(step(m_free, &d_free), StepStatus::kOk) << d_free.last_error;
    EXPECT_EQ(d.stats.contact.activation_loops, 1) << "step " << k;
    gap_predicted = std::max(gap_predicted, largestActiveGap(d));
    if (k < 300) continue;
    moved = std::max(moved, largestNodeDistance(d.devices, before));
    moved_free = std::max(moved_free, largestNodeDistance(d_free.devices, before_free));
  }
  std::printf(
      "[ metric   ] carotid at rest: largest |gap| of an active contact %.3g m from x_f, %.3g m "
      "predicted; a node moves <= %.3g m per step at steps 300-400 (%.3g m without the "
      "prediction)\n",
      gap_free, gap_predicted, moved, moved_free);
  EXPECT_LT(gap_predicted, 1e-9);
  // At rest as the wire is without it: no more motion than its own settling.
  EXPECT_LT(moved, moved_free + 1e-9);
}

}  // namespace
}  // namespace evsim
