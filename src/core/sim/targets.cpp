// Navigation targets: a named vessel the distal tip of a device must reach and
// stay in. Declared and documented in endovascular_sim/sim/targets.h.
#include "endovascular_sim/sim/targets.h"

#include <algorithm>
#include <sstream>

namespace evsim {

namespace {

/// A vessel target: the first device (of those it accepts) whose tip is
/// deep enough inside the vessel now (requiredDepth) (-1: none); best_depth follows the tips.
int deepTip(const Target& target, const std::vector<VesselLocation>& tips, const VesselAtlas& atlas,
            TargetProgress* p) {
  const double required = requiredDepth(atlas.vessels()[target.vessel], target.spec.depth);
  int deep = -1;
  for (size_t i = 0; i < tips.size(); ++i) {
    if (target.device >= 0 && target.device != static_cast<int>(i)) continue;
    if (tips[i].vessel != target.vessel || !tips[i].inside) continue;
    p->best_depth = std::max(p->best_depth, tips[i].depth);
    if (tips[i].depth >= required && deep < 0) deep = static_cast<int>(i);
  }
  return deep;
}

/// An aneurysm target: the share [-] of the coil's nodes (those beyond the
/// element cut on detach) in the sac: outside every vessel's lumen, within
/// 1.5 dome radii of its centre (the blended dome and its neck); 0 before
/// the coil is detached.
double coilInside(const Target& target, const DeviceModel& m, const DeviceState& s,
                  const VesselAtlas& atlas) {
  if (s.cut_element < 0 || m.detach_element < 0) return 0.0;  // not detached
  int inside = 0, count = 0;
  for (int i = m.detach_element + 1; i < m.num_nodes; ++i, ++count)
    if ((s.position[i] - target.center).norm() <= 1.5 * target.radius &&
        !atlas.locate(s.position[i]).inside)
      ++inside;
  return count > 0 ? static_cast<double>(inside) / count : 0.0;
}

}  // namespace

double requiredDepth(const NamedVessel& vessel, double depth) {
  return std::min(depth, 0.5 * vessel.length);
}

std::vector<std::string> updateTargets(const std::vector<Target>& targets,
                                       const std::vector<VesselLocation>& tips,
                                       const std::vector<DeviceModel>& models,
                                       const std::vector<DeviceState>& devices,
                                       const VesselAtlas& atlas, double t,
                                       std::vector<TargetProgress>* progress) {
  std::vector<std::string> notices;
  progress->resize(targets.size());
  for (size_t k = 0; k < targets.size(); ++k) {
    const Target& target = targets[k];
    TargetProgress& p = (*progress)[k];
    int by = -1;  // the device that holds the target now
    if (target.spec.aneurysm >= 0) {
      const double share = coilInside(target, models[target.device], devices[target.device], atlas);
      p.best_inside = std::max(p.best_inside, share);
      if (share >= 1.0) by = target.device;
    } else {
      by = deepTip(target, tips, atlas, &p);
    }
    if (by < 0) {
      p.since = -1.0;
      continue;
    }
    if (p.since < 0.0) p.since = t;
    if (p.reached || t - p.since < target.spec.dwell - 1e-9) continue;
    p.reached = true;
    p.reached_time = t;
    std::ostringstream m;
    if (target.spec.aneurysm >= 0)
      m << "target '" << target.spec.label() << "' reached: the " << models[by].name
        << "'s detached coil in the sac since t = " << p.since << " s (at t = " << t << " s)";
    else
      m << "target '" << target.spec.label() << "' reached by the " << models[by].name
        << "'s tip at t = " << t << " s (" << tips[by].depth * 1e3 << " mm inside)";
    notices.push_back(m.str());
  }
  return notices;
}

}  // namespace evsim
