// Checks of a step's answer shared by the tests that step one state two
// ways (an option on and off): Signorini's law on the contacts, and how far
// the two answers lie apart.
#pragma once

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

}  // namespace evsim::test
