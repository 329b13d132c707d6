// A navigation baseline. Declared and documented in
// endovascular_sim/sim/autopilot.h.
#include "endovascular_sim/sim/autopilot.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "endovascular_sim/core/load_error.h"

namespace evsim {

const char* phaseName(AutopilotPhase phase) {
  switch (phase) {
    case AutopilotPhase::kAdvance:
      return "advance";
    case AutopilotPhase::kAim:
      return "aim";
    case AutopilotPhase::kRetract:
      return "retract";
    case AutopilotPhase::kDwell:
      return "dwell";
    case AutopilotPhase::kReached:
      return "reached";
    case AutopilotPhase::kFailed:
      return "failed";
  }
  return "?";
}

namespace {

constexpr double kOuterMinLead = 0.005;  // [m] the inner device's drive ahead of the outer's

/// Index of the last node at least `back` [m] (material) behind the tip.
int nodeBehindTip(const DeviceModel& m, double back) {
  int i = m.num_nodes - 1;
  while (i > 0 && m.node_s[i] > m.length - back) --i;
  return i;
}

}  // namespace

double shapedLength(const DeviceModel& m) {
  const int last = m.element_section.back();
  int first = static_cast<int>(m.element_section.size()) - 1;
  while (first > 0 && m.element_section[first - 1] == last) --first;
  return m.length - m.node_s[first];
}

bool offPlan(const VesselAtlas& atlas, const std::vector<int>& plan, int vessel, const Vec3& tip) {
  return std::find(plan.begin(), plan.end(), vessel) == plan.end() &&
         std::none_of(plan.begin(), plan.end(),
                      [&](int on) { return atlas.locateIn(on, tip).inside; });
}

Autopilot::Autopilot(const SceneModel& model, const SimData& data, const std::string& target,
                     const std::string& device, const AutopilotOptions& options)
    : options_(options) {
  auto refuse = [&](const std::string& why) { throw LoadError(model.file, 0, "target", why); };
  if (!model.atlas) refuse("scene '" + model.name + "' has no vessels to navigate");
  const VesselAtlas& atlas = *model.atlas;
  target_ = atlas.find(target);
  if (target_ < 0) {
    std::string near;
    for (const std::string& n : atlas.closestNames(target)) near += (near.empty() ? "" : ", ") + n;
    refuse("no vessel '" + target + "' in scene '" + model.name + "' (" +
           std::to_string(atlas.vessels().size()) + " named vessels; nearest: " + near + ")");
  }
  const int n = static_cast<int>(model.devices.size());
  if (!device.empty()) {
    lead_ = findDevice(model, device);
    if (lead_ < 0) refuse("no device '" + device + "' in scene '" + model.name + "'");
  } else {  // the innermost device: no other device runs inside it
    for (int i = 0; i < n && lead_ < 0; ++i) {
      bool outer_of_another = false;
      for (int j = 0; j < n && !model.outer_of.empty(); ++j)
        outer_of_another |= model.outer_of[j] == i;
      if (!outer_of_another) lead_ = i;
    }
  }
  follow_ = model.outer_of.empty() ? -1 : model.outer_of[lead_];
  const double tip_radius = model.devices[lead_].node_radius.back();
  if (atlas.vessels()[target_].radius <= tip_radius) {
    std::ostringstream why;
    why << "vessel '" << target << "' narrows to " << atlas.vessels()[target_].radius * 1e3
        << " mm radius; the tip of device '" << model.devices[lead_].name << "' is "
        << tip_radius * 1e3 << " mm: the lumen is closed to it";
    refuse(why.str());
  }
  entry_vessel_ = data.tips.at(lead_).vessel;
  if (atlas.path(entry_vessel_, target_).empty())
    refuse("vessel '" + target + "' is not connected to vessel '" +
           atlas.vessels()[entry_vessel_].name + "', where the tip of device '" +
           model.devices[lead_].name + "' is");
  start_time_ = data.time;
  start_inserted_ = data.devices.at(lead_).inserted_length;
  next_tick_ = data.time;
  progress_time_ = data.time;
  current_vessel_ = entry_vessel_;
  // From the start, not from the first control tick: a client's first
  // feedback may come before the first step.
  goal_depth_ = requiredDepth(atlas.vessels()[target_], options_.depth);
  report_.remaining_path =
      atlas.pathLength(atlas.path(entry_vessel_, target_), data.tips.at(lead_).depth, goal_depth_);
}

double Autopilot::retractFloor(double inserted) const {
  return std::max(inserted, 0.5 * start_inserted_);
}

std::string Autopilot::setPhase(AutopilotPhase phase, const std::string& why, double t) {
  if (phase == phase_) return "";
  phase_ = phase;
  std::ostringstream line;
  line << "t=" << t << " s  " << phaseName(phase) << (why.empty() ? "" : ": " + why);
  return line.str();
}

void Autopilot::fail(const std::string& why, double t) {
  phase_ = AutopilotPhase::kFailed;
  report_.reached = false;
  report_.reason = why;
  report_.time = t - start_time_;
}

void Autopilot::drive(const SceneModel& model, SimData* data, double insertion_speed,
                      double rotation_speed) {
  const DeviceModel& m = model.devices[lead_];
  DriveCommand lead;
  lead.insertion = std::clamp(insertion_speed, -m.max_insertion_speed, m.max_insertion_speed);
  lead.rotation = std::clamp(rotation_speed, -m.max_rotation_speed, m.max_rotation_speed);
  applyCommand(data, lead_, lead);
  if (follow_ < 0) return;
  // The outer device keeps its tip follow_lag behind the inner one's, but
  // goes no deeper once its tip is in a vessel too narrow for it (less than
  // options_.outer_fit times its radius): the wire goes on alone, as beyond
  // a guiding catheter.
  const DeviceModel& o = model.devices[follow_];
  DriveCommand outer;
  outer.mode = DriveCommand::Mode::kPosition;
  // Advancing, it never draws back to the lag: a catheter already deeper
  // (engaged in a branch) would pull the wire's tip out of it.
  // Retracting, it holds where it is while its tip is in a vessel of the
  // plan: the wire draws back into it and tries the fork ahead again (drawn
  // back to the lag, a catheter that leads past a fork would leave it).
  const double lead_inserted = data->devices[lead_].inserted_length;
  const double outer_inserted = data->devices[follow_].inserted_length;
  double behind = lead_inserted - options_.follow_lag;
  if (insertion_speed >= 0.0) {
    behind = std::max(behind, std::min(outer_inserted, lead_inserted - kOuterMinLead));
  } else {
    const std::vector<int> plan = model.atlas->path(entry_vessel_, target_);
    if (std::find(plan.begin(), plan.end(), data->tips[follow_].vessel) != plan.end())
      behind = std::max(behind, outer_inserted);
  }
  outer.insertion = std::clamp(behind, 0.0, o.length);
  const int outer_vessel = data->tips[follow_].vessel;
  if (outer_vessel >= 0 &&
      model.atlas->vessels()[outer_vessel].radius < options_.outer_fit * o.node_radius.back())
    outer.insertion = std::min(outer.insertion, data->devices[follow_].inserted_length);
  outer.rotation = data->devices[follow_].rotation_angle;
  applyCommand(data, follow_, outer);
}

Autopilot::Aim Autopilot::aimFor(const SceneModel& model, const SimData& data, int device,
                                 const std::vector<int>& path) const {
  const VesselAtlas& atlas = *model.atlas;
  const VesselLocation& at = data.tips[device];
  const NamedVessel& here = atlas.vessels()[at.vessel];
  Aim aim;
  if (path.size() < 2) return aim;
  const int next = path[1];
  // Direction of travel along the current vessel: toward the next junction.
  double sign = -1.0;  // toward the origin (the next vessel is the parent)
  if (atlas.vessels()[next].parent == at.vessel)
    sign = atlas.vessels()[next].origin_depth >= at.depth ? 1.0 : -1.0;
  // The nearest ostium of the current vessel ahead of the tip (or just
  // passed): turn toward it when it is the path's, away from it otherwise.
  double best = 1e9;
  for (int child : here.children) {
    // The parent's continuation is where a tip goes anyway: it turns away
    // from the other daughters there, as from a side branch's ostium.
    if (child == next && isContinuation(atlas, child)) continue;
    const NamedVessel& c = atlas.vessels()[child];
    const double ahead = (c.origin_depth - at.depth) * sign;
    const double window = here.radius + options_.approach_distance;
    if (ahead > window || ahead < -(c.radius + 0.003)) continue;
    // The nearest; of a bifurcation's two (at one depth), the path's.
    const double distance = std::abs(ahead);
    if (distance > best + 1e-6 || (distance >= best - 1e-6 && child != next && aim.toward_path))
      continue;
    best = distance;
    Vec3 start_dir;
    const Vec3 start = atlas.pointAt(child, 0.0, &start_dir);
    const Vec3 out = atlas.pointAt(child, std::min(c.length, 1.5 * here.radius + 0.005));
    const Vec3 dir = (out - start).normalized();
    aim.wanted = true;
    aim.toward_path = child == next;
    aim.direction = aim.toward_path ? dir : Vec3(-dir);
    aim.distance = std::abs(ahead);
  }
  // Toward the origin of a vessel that starts at its parent's end (a
  // patient's file rooted upstream, at the aortic root, splits the aorta
  // there): its siblings leave at that fork. The tip turns toward the
  // path's sibling if one is, else toward the parent's own course back
  // from the fork (the arch's, past the subclavian's ostium): turning away
  // from a sibling that leaves straight ahead asks for no sideways turn.
  if (!aim.wanted && next == here.parent && next >= 0 && at.depth <= best &&
      at.depth <= here.radius + options_.approach_distance) {
    const NamedVessel& parent = atlas.vessels()[next];
    const double reach = 1.5 * parent.radius + 0.005;
    bool fork = false;
    for (int sibling : parent.children) {
      const NamedVessel& c = atlas.vessels()[sibling];
      if (sibling == at.vessel || std::abs(c.origin_depth - here.origin_depth) > 1e-6) continue;
      fork = true;
      if (path.size() > 2 && path[2] == sibling) {
        aim.direction =
            (atlas.pointAt(sibling, std::min(c.length, reach)) - atlas.pointAt(sibling, 0.0))
                .normalized();
        aim.toward_parent = false;
        break;
      }
      aim.direction = (atlas.pointAt(next, std::max(0.0, here.origin_depth - reach)) -
                       atlas.pointAt(next, here.origin_depth))
                          .normalized();
      aim.toward_parent = true;
    }
    aim.wanted = fork;
    aim.toward_path = fork;
    aim.distance = at.depth;
  }
  return aim;
}

double Autopilot::tipBendAngle(const SceneModel& model, const SimData& data, int device,
                               const Vec3& want) const {
  const DeviceModel& m = model.devices[device];
  const std::vector<Vec3>& x = data.devices[device].position;
  // The shaft's direction just behind the tip's section (its shaped part).
  const double shaped = shapedLength(m);
  const int back1 = nodeBehindTip(m, shaped + 0.003), back2 = nodeBehindTip(m, shaped + 0.013);
  if (back2 >= back1) return 0.0;
  const Vec3 shaft = (x[back1] - x[back2]).normalized();
  Vec3 bend = x.back() - x[back1];
  bend -= bend.dot(shaft) * shaft;
  Vec3 w = want - want.dot(shaft) * shaft;
  if (bend.norm() < 1e-4 || w.norm() < 1e-6) return 0.0;  // a straight tip, or no sideways aim
  bend.normalize();
  w.normalize();
  return std::atan2(shaft.dot(bend.cross(w)), bend.dot(w));
}

double Autopilot::turningPace(bool turning, double t) {
  if (!turning) {
    turning_since_ = -1.0;
    return 1.0;
  }
  if (turning_since_ < 0.0) turning_since_ = t;
  return t - turning_since_ > options_.probe_after ? options_.probe_pace : 0.0;
}

double Autopilot::searchTurn(double turn) const {
  static constexpr double kOffsets[] = {0.0, 0.6, -0.6, 1.2, -1.2, M_PI};
  return std::remainder(turn + kOffsets[report_.retries % 6], 2 * M_PI);
}

std::string Autopilot::retryWhy(const VesselAtlas& atlas, const std::vector<int>& plan,
                                const std::vector<int>& path, const VesselLocation& at,
                                const Vec3& tip, double remaining, double t, double* pull) const {
  std::string retry;
  if (offPlan(atlas, plan, at.vessel, tip)) {  // a wrong vessel
    retry = "entered " + atlas.vessels()[at.vessel].name;
    *pull =
        at.depth +
        atlas
            .vessels()[atlas.vessels()[at.vessel].parent >= 0 ? atlas.vessels()[at.vessel].parent
                                                              : at.vessel]
            .radius +
        0.01;
  } else if (path.size() >= 2 && atlas.vessels()[path[1]].parent == at.vessel) {
    const NamedVessel& next = atlas.vessels()[path[1]];
    const double passed = std::abs(at.depth - next.origin_depth);
    const bool beyond = passed > atlas.vessels()[at.vessel].radius + next.radius + 0.01 &&
                        remaining > best_remaining_ + 0.005;
    if (beyond) {
      retry = "slid past the ostium of " + next.name;
      *pull = passed + 0.01;
    }
  }
  if (retry.empty() && t - progress_time_ > options_.stuck_time) {
    retry = "no progress for " + std::to_string(options_.stuck_time) + " s";
    *pull = 0.02;
  }
  return retry;
}

bool Autopilot::judgeDwell(const SceneModel& model, const SimData& data) {
  Target goal;
  goal.spec.vessel = model.atlas->vessels()[target_].name;
  goal.spec.depth = options_.depth;
  goal.spec.dwell = options_.dwell;
  goal.vessel = target_;
  goal.device = lead_;
  updateTargets({goal}, data.tips, model.devices, data.devices, *model.atlas, data.time,
                &goal_progress_);
  return goal_progress_[0].reached;
}

std::string Autopilot::control(const SceneModel& model, SimData* data) {
  const double t = data->time;
  if (done()) return "";
  // The dwell is judged at every step, as the scene's targets are.
  if (judgeDwell(model, *data)) {
    phase_ = AutopilotPhase::kReached;
    report_.reached = true;
    report_.reason.clear();
    report_.time = t - start_time_;
    drive(model, data, 0.0, 0.0);
    return "t=" + std::to_string(t) + " s  reached " + model.atlas->vessels()[target_].name;
  }
  if (t + 1e-12 < next_tick_) return "";
  next_tick_ = t + options_.control_period;
  const VesselAtlas& atlas = *model.atlas;
  const VesselLocation at = data->tips[lead_];
  current_vessel_ = at.vessel;
  const std::vector<int> path = atlas.path(at.vessel, target_);
  const std::vector<int> plan = atlas.path(entry_vessel_, target_);

  const double remaining = atlas.pathLength(path, at.depth, goal_depth_);
  report_.remaining_path = remaining;
  report_.time = t - start_time_;
  if (remaining < best_remaining_ - 0.002) {
    best_remaining_ = remaining;
    progress_time_ = t;
  }
  if (t - start_time_ > options_.timeout) {
    fail("out of time", t);
    drive(model, data, 0.0, 0.0);
    return "t=" + std::to_string(t) + " s  failed: out of time";
  }
  if (follow_ >= 0 && stage_ != PairStage::kOver) {
    const std::string pair = controlPair(model, data, path, t);
    if (stage_ != PairStage::kOver) return pair;
  }
  return steerLead(model, data, plan, path, at, remaining);
}

std::string Autopilot::steerLead(const SceneModel& model, SimData* data,
                                 const std::vector<int>& plan, const std::vector<int>& path,
                                 const VesselLocation& at, double remaining) {
  const double t = data->time;
  const VesselAtlas& atlas = *model.atlas;
  const DeviceState& lead = data->devices[lead_];
  const Aim aim = aimFor(model, *data, lead_, path);
  double turn = aim.wanted ? tipBendAngle(model, *data, lead_, aim.direction) : 0.0;
  // Away from an ostium off the path: each retry tries another quarter turn.
  if (aim.wanted && !aim.toward_path)
    turn = std::remainder(turn + 0.5 * M_PI * report_.retries, 2 * M_PI);
  else if (aim.wanted)
    turn = searchTurn(turn);
  // Near a half turn the sign is noise: keep turning the way it turned.
  if (std::abs(turn) > 2.5 && last_turn_ != 0.0) turn = std::copysign(std::abs(turn), last_turn_);
  last_turn_ = turn;
  const double rotation = options_.rotation_gain * turn;
  std::string line;

  if (phase_ == AutopilotPhase::kRetract) {
    if (lead.inserted_length > retract_until_) {
      drive(model, data, -options_.retract_speed, rotation);
      return "";
    }
    line = setPhase(AutopilotPhase::kAdvance, "", t);
    best_remaining_ = remaining;
    progress_time_ = t;
  }

  const bool in_target = at.vessel == target_ && at.inside;
  if (in_target && at.depth >= goal_depth_) {
    // A few millimetres deeper than needed (a quarter of a short vessel's
    // length), then hold still for the dwell.
    const double margin = std::min(0.005, 0.25 * atlas.vessels()[target_].length);
    drive(model, data, at.depth < goal_depth_ + margin ? 0.5 * options_.advance_speed : 0.0, 0.0);
    const std::string d =
        setPhase(AutopilotPhase::kDwell, "in " + atlas.vessels()[target_].name, t);
    return line.empty() ? d : line + "\n" + d;
  }
  // Wrong vessel, slid past the ostium, or stuck: pull back and try again.
  double pull = 0.0;
  const std::string retry =
      retryWhy(atlas, plan, path, at, lead.position.back(), remaining, t, &pull);
  if (!retry.empty()) {
    if (++report_.retries > options_.max_retries) {
      fail("retries exhausted (" + std::to_string(options_.max_retries) + "), last: " + retry, t);
      drive(model, data, 0.0, 0.0);
      return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
    }
    retract_until_ = retractFloor(lead.inserted_length - pull);
    progress_time_ = t;
    best_remaining_ = 1e9;
    drive(model, data, -options_.retract_speed, rotation);
    const std::string r = setPhase(AutopilotPhase::kRetract, retry, t);
    return line.empty() ? r : line + "\n" + r;
  }

  // Near an ostium of the path: turn first, then advance.
  const bool hold = aim.wanted && aim.toward_path && std::abs(turn) > options_.aim_tolerance;
  drive(model, data, turningPace(hold, t) * options_.advance_speed, rotation);
  const std::string p = setPhase(
      hold ? AutopilotPhase::kAim : AutopilotPhase::kAdvance,
      hold ? "toward " + atlas.vessels()[path[1]].name : "in " + atlas.vessels()[at.vessel].name,
      t);
  return line.empty() ? p : (p.empty() ? line : line + "\n" + p);
}

void Autopilot::observe(const SimData& data, bool step_failed) {
  if (step_failed) ++report_.failed_steps;
  report_.peak_wall_force = std::max(report_.peak_wall_force, maxWallForce(data));
}

}  // namespace evsim
