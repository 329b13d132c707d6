// contact.slid_pair_warm_start: a new element pair found at the first
// iterate next to a pair kept from the last step with a force takes that
// force over as the LCP's warm start (the contact slid past a node). A warm
// start changes where the status method starts, not where it ends (the
// packed coil's LCPs have one answer: status method and block principal
// pivoting agree to 1e-13 on z). The reference is the same step started
// with the force left where it was: each step from one state both ways, the
// answers must obey Signorini's law alike and lie within the pair tolerance
// of each other, in fewer pivots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "endovascular_sim/sim/simulation.h"
#include "signorini_check.h"

namespace evsim {
namespace {

// The coil of `aneurysm_packed` filling its dome at t = 4.5-4.8 s: its
// turns slide along each other as it is pushed in.
TEST(SlidPairWarmStart, TakenOverForcesGiveTheSameAnswerInFewerPivots) {
  SceneModel taking = loadScene("aneurysm_packed");
  ASSERT_TRUE(taking.contact.slid_pair_warm_start);  // the default
  SceneModel leaving = taking;
  leaving.contact.slid_pair_warm_start = false;
  const double tol = std::max(taking.contact.penetration_tolerance, taking.contact.pair_tolerance);
  SimData d = makeData(taking);
  for (int k = 0; k < 4500; ++k) ASSERT_EQ(step(taking, &d), StepStatus::kOk) << d.last_error;
  long pivots_taking = 0, pivots_leaving = 0, loops_taking = 0, loops_leaving = 0, slid = 0;
  double gap_taking = 0.0, gap_leaving = 0.0, apart = 0.0;
  for (int k = 0; k < 300; ++k) {
    SimData other = d;
    ASSERT_EQ(step(leaving, &other), StepStatus::kOk) << "step " << k << ": " << other.last_error;
    ASSERT_EQ(step(taking, &d), StepStatus::kOk) << "step " << k << ": " << d.last_error;
    EXPECT_EQ(other.stats.slid_forces, 0) << "step " << k;
    slid += d.stats.slid_forces;
    pivots_taking += d.stats.lcp_iterations;
    pivots_leaving += other.stats.lcp_iterations;
    loops_taking += d.stats.activation_loops;
    loops_leaving += other.stats.activation_loops;
    gap_taking = std::max(gap_taking, test::largestActiveGap(d));
    gap_leaving = std::max(gap_leaving, test::largestActiveGap(other));
    apart = std::max(apart, test::largestNodeDistance(d.devices, other.devices));
  }
  std::printf(
      "[ metric   ] aneurysm_packed t = 4.5-4.8 s: %ld forces taken over; status-method pivots "
      "%ld taken over, %ld left; loops %ld and %ld; largest |gap| of an active contact %.3g m "
      "and %.3g m; answers %.3g m apart at most\n",
      slid, pivots_taking, pivots_leaving, loops_taking, loops_leaving, gap_taking, gap_leaving,
      apart);
  EXPECT_GT(slid, 100);
  EXPECT_LT(pivots_taking, pivots_leaving - pivots_leaving / 10);
  EXPECT_LE(gap_taking, tol);
  EXPECT_LE(gap_leaving, tol);
  EXPECT_LE(apart, tol);
  EXPECT_LE(loops_taking, loops_leaving + loops_leaving / 20);
}

}  // namespace
}  // namespace evsim
