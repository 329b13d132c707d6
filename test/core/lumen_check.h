// An independent check of the coaxial effect's answer: every sample point of
// every inner device located in its outer device's lumen, one by one (the
// activation loop plans planes for some of them only).
#pragma once

#include <algorithm>

#include "endovascular_sim/contact/coaxial.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim::test {

/// Deepest sample point of any inner device beyond its outer device's lumen
/// [m] (0 when every point is inside, or the scene has no coaxial pair).
inline double worstLumenExcess(const SceneModel& m, const SimData& d) {
  double worst = 0.0;
  for (size_t i = 0; i < m.outer_of.size(); ++i) {
    const int o = m.outer_of[i];
    if (o < 0) continue;
    for (const SamplePoint& s : m.samples[i]) {
      const LumenLocation loc =
          locateInLumen(m.devices[i], d.devices[i], s, m.devices[o], d.devices[o]);
      if (loc.inside) worst = std::max(worst, loc.excess());
    }
  }
  return worst;
}

}  // namespace evsim::test
