#include "endovascular_sim/sim/targets.h"

#include <sstream>

namespace evsim {

std::vector<std::string> updateTargets(const std::vector<Target>& targets,
                                       const std::vector<VesselLocation>& tips,
                                       const std::vector<std::string>& device_names,
                                       const VesselAtlas& atlas, double t,
                                       std::vector<TargetProgress>* progress) {
  std::vector<std::string> notices;
  progress->resize(targets.size());
  for (size_t k = 0; k < targets.size(); ++k) {
    const Target& target = targets[k];
    TargetProgress& p = (*progress)[k];
    int deep = -1;  // a device whose tip is deep enough in the vessel now
    for (size_t i = 0; i < tips.size(); ++i) {
      if (target.device >= 0 && target.device != static_cast<int>(i)) continue;
      if (tips[i].vessel != target.vessel || !tips[i].inside) continue;
      p.best_depth = std::max(p.best_depth, tips[i].depth);
      if (tips[i].depth >= target.spec.depth && deep < 0) deep = static_cast<int>(i);
    }
    if (deep < 0) {
      p.since = -1.0;
      continue;
    }
    if (p.since < 0.0) p.since = t;
    if (p.reached || t - p.since < target.spec.dwell - 1e-9) continue;
    p.reached = true;
    p.reached_time = t;
    std::ostringstream m;
    m << "target '" << atlas.vessels()[target.vessel].name << "' reached by the "
      << device_names[deep] << "'s tip at t = " << t << " s (" << tips[deep].depth * 1e3
      << " mm inside)";
    notices.push_back(m.str());
  }
  return notices;
}

}  // namespace evsim
