// Checks of a step's answer shared by the tests that step one state two
// ways (an option on and off): Signorini's law on the contacts, and how far
// the two answers lie apart.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "endovascular_sim/sim/simulation.h"

namespace evsim::test {

/// The largest |gap| of a contact that carries a force [m]: Signorini's
/// law wants 0.
inline double largestActiveGap(const SimData& d) {
  double worst = 0.0;
  for (const Contact& c : d.contacts)
    if (c.force > 0.0) worst = std::max(worst, std::abs(c.gap));
  return worst;
}

/// Largest distance between the nodes of two sets of states [m].
inline double largestNodeDistance(const std::vector<DeviceState>& a,
                                  const std::vector<DeviceState>& b) {
  double worst = 0.0;
  for (size_t d = 0; d < a.size(); ++d)
    for (size_t i = 0; i < a[d].position.size(); ++i)
      worst = std::max(worst, (a[d].position[i] - b[d].position[i]).norm());
  return worst;
}

/// An answer within the tolerance: no point beyond the wall, and no
/// contact's gap below, by more than tol [m] (step k, for the message).
inline void expectWithinTolerance(const SimData& d, double tol, int k) {
  EXPECT_LE(d.stats.contact.max_penetration_m, tol) << "step " << k;
  for (const Contact& c : d.contacts) EXPECT_GE(c.gap, -tol) << "step " << k;
}

/// What the tests that step one state two ways (a and b) add up: the
/// activation loops of each, the largest |gap| of an active contact of
/// each [m], and how far apart their answers lie at most [m].
struct BothWays {
  long loops_a{0}, loops_b{0};
  double gap_a{0.0}, gap_b{0.0}, apart{0.0};
  void add(const SimData& a, const SimData& b) {
    loops_a += a.stats.contact.activation_loops;
    loops_b += b.stats.contact.activation_loops;
    gap_a = std::max(gap_a, largestActiveGap(a));
    gap_b = std::max(gap_b, largestActiveGap(b));
    apart = std::max(apart, largestNodeDistance(a.devices, b.devices));
  }
};

/// Steps scene `a` `warmup` times, then `steps` times, each step also
/// taken from the same state with scene `b` (an option on and off), and
/// calls visit(k, after_a, after_b) after each. A failed step is a fatal
/// failure (the caller's ASSERT_NO_FATAL_FAILURE stops there).
template <typename Visit>
void stepBothWays(const SceneModel& a, const SceneModel& b, int warmup, int steps, Visit&& visit) {
  SimData d = makeData(a);
  for (int k = 0; k < warmup; ++k) ASSERT_EQ(step(a, &d), StepStatus::kOk) << d.last_error;
  for (int k = 0; k < steps; ++k) {
    SimData other = d;
    ASSERT_EQ(step(b, &other), StepStatus::kOk) << "step " << k << ": " << other.last_error;
    ASSERT_EQ(step(a, &d), StepStatus::kOk) << "step " << k << ": " << d.last_error;
    visit(k, static_cast<const SimData&>(d), static_cast<const SimData&>(other));
  }
}

}  // namespace evsim::test
