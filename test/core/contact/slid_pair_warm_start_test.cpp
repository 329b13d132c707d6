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
  long pivots_taking = 0, pivots_leaving = 0, slid = 0;
  test::BothWays t;  // a: taken over, b: left where it was
  ASSERT_NO_FATAL_FAILURE(test::stepBothWays(
      taking, leaving, 4500, 300, [&](int k, const SimData& d, const SimData& other) {
        EXPECT_EQ(other.stats.contact.slid_forces, 0) << "step " << k;
        test::expectWithinTolerance(d, tol, k);
        t.add(d, other);
        slid += d.stats.contact.slid_forces;
        pivots_taking += d.stats.contact.lcp_iterations;
        pivots_leaving += other.stats.contact.lcp_iterations;
      }));
  std::printf(
      "[ metric   ] aneurysm_packed t = 4.5-4.8 s: %ld forces taken over; status-method pivots "
      "%ld taken over, %ld left; loops %ld and %ld; largest |gap| of an active contact %.3g m "
      "and %.3g m; answers %.3g m apart at most\n",
      slid, pivots_taking, pivots_leaving, t.loops_a, t.loops_b, t.gap_a, t.gap_b, t.apart);
  EXPECT_GT(slid, 100);
  EXPECT_LT(pivots_taking, pivots_leaving - pivots_leaving / 10);
  EXPECT_LE(t.gap_a, tol);
  EXPECT_LE(t.gap_b, tol);
  EXPECT_LE(t.apart, tol);
  EXPECT_LE(t.loops_a, t.loops_b + t.loops_b / 20);
}

}  // namespace
}  // namespace evsim
