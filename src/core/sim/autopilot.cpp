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

/// Index of the last node at least `back` [m] (material) behind the tip.
int nodeBehindTip(const DeviceModel& m, double back) {
  int i = m.num_nodes - 1;
  while (i > 0 && m.node_s[i] > m.length - back) --i;
  return i;
}

}  // namespace

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
  next_tick_ = data.time;
  progress_time_ = data.time;
  current_vessel_ = entry_vessel_;
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
  data->commands[lead_] = lead;
  if (follow_ < 0) return;
  // The outer device keeps its tip follow_lag behind the inner one's, but
  // goes no deeper once its tip is in a vessel too narrow for it (less than
  // twice its radius): the wire goes on alone, as beyond a guiding catheter.
  const DeviceModel& o = model.devices[follow_];
  DriveCommand outer;
  outer.mode = DriveCommand::Mode::kPosition;
  outer.insertion =
      std::clamp(data->devices[lead_].inserted_length - options_.follow_lag, 0.0, o.length);
  const int outer_vessel = data->tips[follow_].vessel;
  if (outer_vessel >= 0 && model.atlas->vessels()[outer_vessel].radius < 2.0 * o.node_radius.back())
    outer.insertion = std::min(outer.insertion, data->devices[follow_].inserted_length);
  outer.rotation = data->devices[follow_].rotation_angle;
  data->commands[follow_] = outer;
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
    const NamedVessel& c = atlas.vessels()[child];
    const double ahead = (c.origin_depth - at.depth) * sign;
    const double window = here.radius + options_.approach_distance;
    if (ahead > window || ahead < -(c.radius + 0.003)) continue;
    if (std::abs(ahead) >= best) continue;
    best = std::abs(ahead);
    Vec3 start_dir;
    const Vec3 start = atlas.pointAt(child, 0.0, &start_dir);
    const Vec3 out = atlas.pointAt(child, std::min(c.length, 1.5 * here.radius + 0.005));
    const Vec3 dir = (out - start).normalized();
    aim.wanted = true;
    aim.toward_path = child == next;
    aim.direction = aim.toward_path ? dir : Vec3(-dir);
    aim.distance = std::abs(ahead);
  }
  return aim;
}

double Autopilot::tipBendAngle(const SceneModel& model, const SimData& data, int device,
                               const Vec3& want) const {
  const DeviceModel& m = model.devices[device];
  const std::vector<Vec3>& x = data.devices[device].position;
  // The shaft's direction just behind the tip's section (its shaped part).
  const int last = m.element_section.back();
  int first = static_cast<int>(m.element_section.size()) - 1;
  while (first > 0 && m.element_section[first - 1] == last) --first;
  const double shaped = m.length - m.node_s[first];
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

std::string Autopilot::control(const SceneModel& model, SimData* data) {
  const double t = data->time;
  if (done()) return "";
  // The dwell is judged at every step, as the scene's targets are.
  Target goal;
  goal.spec.vessel = model.atlas->vessels()[target_].name;
  goal.spec.depth = options_.depth;
  goal.spec.dwell = options_.dwell;
  goal.vessel = target_;
  goal.device = lead_;
  std::vector<std::string> names;
  for (const DeviceModel& m : model.devices) names.push_back(m.name);
  updateTargets({goal}, data->tips, names, *model.atlas, t, &goal_progress_);
  if (goal_progress_[0].reached) {
    phase_ = AutopilotPhase::kReached;
    report_.reached = true;
    report_.reason.clear();
    report_.time = t - start_time_;
    drive(model, data, 0.0, 0.0);
    return "t=" + std::to_string(t) + " s  reached " + goal.spec.vessel;
  }
  if (t + 1e-12 < next_tick_) return "";
  next_tick_ = t + options_.control_period;
  const VesselAtlas& atlas = *model.atlas;
  const VesselLocation at = data->tips[lead_];
  current_vessel_ = at.vessel;
  const std::vector<int> path = atlas.path(at.vessel, target_);
  const std::vector<int> plan = atlas.path(entry_vessel_, target_);

  // Path length left: along the current vessel to the next junction, and so on.
  double remaining = 0.0, s = at.depth;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const NamedVessel& next = atlas.vessels()[path[i + 1]];
    if (next.parent == path[i]) {  // down into a branch
      remaining += std::abs(s - next.origin_depth);
      s = 0.0;
    } else {  // up into the parent
      remaining += s;
      s = atlas.vessels()[path[i]].origin_depth;
    }
  }
  remaining += std::max(0.0, options_.depth - s);
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
  const DeviceState& lead = data->devices[lead_];
  const Aim aim = aimFor(model, *data, lead_, path);
  double turn = aim.wanted ? tipBendAngle(model, *data, lead_, aim.direction) : 0.0;
  // Away from an ostium off the path: each retry tries another quarter turn.
  if (aim.wanted && !aim.toward_path)
    turn = std::remainder(turn + 0.5 * M_PI * report_.retries, 2 * M_PI);
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
  if (in_target && at.depth >= options_.depth) {
    // A few millimetres deeper than needed, then hold still for the dwell.
    drive(model, data, at.depth < options_.depth + 0.005 ? 0.5 * options_.advance_speed : 0.0, 0.0);
    const std::string d =
        setPhase(AutopilotPhase::kDwell, "in " + atlas.vessels()[target_].name, t);
    return line.empty() ? d : line + "\n" + d;
  }
  // Wrong vessel, slid past the ostium, or stuck: pull back and try again.
  std::string retry;
  double pull = 0.0;
  if (std::find(plan.begin(), plan.end(), at.vessel) == plan.end() && at.vessel != target_) {
    retry = "entered " + atlas.vessels()[at.vessel].name;
    pull = at.depth +
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
      pull = passed + 0.01;
    }
  }
  if (retry.empty() && t - progress_time_ > options_.stuck_time) {
    retry = "no progress for " + std::to_string(options_.stuck_time) + " s";
    pull = 0.02;
  }
  if (!retry.empty()) {
    if (++report_.retries > options_.max_retries) {
      fail("retries exhausted (" + std::to_string(options_.max_retries) + "), last: " + retry, t);
      drive(model, data, 0.0, 0.0);
      return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
    }
    retract_until_ = std::max(0.0, lead.inserted_length - pull);
    progress_time_ = t;
    best_remaining_ = 1e9;
    drive(model, data, -options_.retract_speed, rotation);
    const std::string r = setPhase(AutopilotPhase::kRetract, retry, t);
    return line.empty() ? r : line + "\n" + r;
  }

  // Near an ostium of the path: turn first, then advance.
  const bool hold = aim.wanted && aim.toward_path && std::abs(turn) > options_.aim_tolerance;
  drive(model, data, hold ? 0.0 : options_.advance_speed, rotation);
  const std::string p = setPhase(
      hold ? AutopilotPhase::kAim : AutopilotPhase::kAdvance,
      hold ? "toward " + atlas.vessels()[path[1]].name : "in " + atlas.vessels()[at.vessel].name,
      t);
  return line.empty() ? p : (p.empty() ? line : line + "\n" + p);
}

std::string Autopilot::controlPair(const SceneModel& model, SimData* data,
                                   const std::vector<int>& path, double t) {
  const VesselAtlas& atlas = *model.atlas;
  const std::vector<int> plan = atlas.path(entry_vessel_, target_);
  // The first turn of the plan into a branch: where the catheter engages.
  // The next turn of the plan into a branch, from the catheter's vessel on.
  const auto cath_on_plan = std::find(plan.begin(), plan.end(), data->tips[follow_].vessel);
  if (cath_on_plan != plan.end()) {
    const size_t from_index = static_cast<size_t>(cath_on_plan - plan.begin());
    int host = -1, branch = -1;
    for (size_t i = from_index; i + 1 < plan.size() && branch < 0; ++i)
      if (atlas.vessels()[plan[i + 1]].parent == plan[i]) {
        host = plan[i];
        branch = plan[i + 1];
        const double from = i == from_index ? data->tips[follow_].depth
                            : atlas.vessels()[plan[i - 1]].parent == host
                                ? atlas.vessels()[plan[i - 1]].origin_depth
                                : 0.0;
        if (branch != branch_) travel_ = atlas.vessels()[branch].origin_depth >= from ? 1.0 : -1.0;
      }
    // The catheter is in the target, no turn is left, or the next branch is
    // too narrow for the catheter (less than twice its radius): the wire
    // goes on alone, the catheter trailing where it fits.
    if (branch < 0 ||
        atlas.vessels()[branch].radius < 2.0 * model.devices[follow_].node_radius.back()) {
      stage_ = PairStage::kOver;
      return "";
    }
    if (branch != branch_ && stage_ != PairStage::kLead) stage_ = PairStage::kLead;
    host_ = host;
    branch_ = branch;
  }
  if (branch_ < 0) {
    stage_ = PairStage::kOver;
    return "";
  }
  const NamedVessel& branch = atlas.vessels()[branch_];
  const NamedVessel& host = atlas.vessels()[host_];
  DeviceState& wire = data->devices[lead_];
  DeviceState& cath = data->devices[follow_];
  const VesselLocation wire_at = data->tips[lead_];
  const VesselLocation cath_at = data->tips[follow_];
  auto command = [&](int device, DriveCommand::Mode mode, double insertion, double rotation) {
    DriveCommand c;
    c.mode = mode;
    const DeviceModel& m = model.devices[device];
    c.insertion = mode == DriveCommand::Mode::kPosition
                      ? std::clamp(insertion, 0.0, m.length)
                      : std::clamp(insertion, -m.max_insertion_speed, m.max_insertion_speed);
    c.rotation = mode == DriveCommand::Mode::kPosition
                     ? rotation
                     : std::clamp(rotation, -m.max_rotation_speed, m.max_rotation_speed);
    data->commands[device] = c;
  };
  auto stage = [&](PairStage next, const std::string& what) {
    if (next == stage_) return std::string();
    stage_ = next;
    std::ostringstream line;
    line << "t=" << t << " s  " << what;
    return line.str();
  };
  const auto pos = DriveCommand::Mode::kPosition;
  const auto vel = DriveCommand::Mode::kVelocity;
  // How far the catheter's tip is past the branch's ostium along the host.
  // (In a vessel branching off the host at the same junction: its depth.)
  double cath_past = -1.0;
  if (cath_at.vessel == host_)
    cath_past = (cath_at.depth - branch.origin_depth) * travel_;
  else if (atlas.vessels()[cath_at.vessel].parent == host_ &&
           std::abs(atlas.vessels()[cath_at.vessel].origin_depth - branch.origin_depth) < 1e-6)
    cath_past = cath_at.depth;
  const bool wire_off_plan = std::find(plan.begin(), plan.end(), wire_at.vessel) == plan.end();
  // The branch's direction out of the host, and the catheter tip's.
  const Vec3 out = (atlas.pointAt(branch_, std::min(branch.length, 1.5 * host.radius + 0.005)) -
                    atlas.pointAt(branch_, 0.0))
                       .normalized();
  const int cn = model.devices[follow_].num_nodes;
  const Vec3 cath_dir = (cath.position[cn - 1] - cath.position[cn - 3]).normalized();
  // Where a bent tip should point to take the branch: toward it, or, where
  // it runs nearly straight on (within 35 degrees of the catheter's tip),
  // away from its sibling: a bent tip pointed ahead turns aside.
  Vec3 take = out;
  if (cath_dir.dot(out) > std::cos(35.0 * M_PI / 180.0))
    for (int sibling : host.children) {
      const NamedVessel& o = atlas.vessels()[sibling];
      if (sibling == branch_ || std::abs(o.origin_depth - branch.origin_depth) > host.radius)
        continue;
      take = -(atlas.pointAt(sibling, std::min(o.length, 1.5 * host.radius + 0.005)) -
               atlas.pointAt(sibling, 0.0))
                  .normalized();
    }
  const VesselLocation cath_in_branch = atlas.locateIn(branch_, cath.position.back());
  const bool engaged = (cath_at.vessel == branch_ ||
                        (cath_in_branch.inside && cath_in_branch.depth >= 0.6 * host.radius)) &&
                       cath_dir.dot(out) > 0.5;
  if (engaged && (stage_ == PairStage::kLead || stage_ == PairStage::kEngage)) {
    command(follow_, vel, 0.0, 0.0);
    return stage(PairStage::kWireIn, "catheter engaged in " + branch.name + "; wire in");
  }

  switch (stage_) {
    case PairStage::kLead: {
      if (!wire_off_plan && std::find(plan.begin(), plan.end(), wire_at.vessel) >=
                                std::find(plan.begin(), plan.end(), branch_)) {
        progress_time_ = t;
        return stage(PairStage::kFollow, "the wire is in " + branch.name + "; catheter follows");
      }
      if (wire_off_plan) {  // into a wrong vessel: both back out of it
        if (++report_.retries > options_.max_retries) {
          fail("retries exhausted (" + std::to_string(options_.max_retries) + ")", t);
          return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
        }
        retract_until_ = std::max(0.0, wire.inserted_length - wire_at.depth - host.radius - 0.01);
        return stage(PairStage::kBackOut, "back out of " + atlas.vessels()[wire_at.vessel].name);
      }
      const bool terminal = branch.origin_depth >= host.length - 1e-4 ||
                            branch.origin_depth <= 1e-4;  // the host ends in the bifurcation
      if (terminal ? cath_past > -(host.radius + 0.003) : cath_past > branch.radius + 0.005) {
        command(lead_, pos, cath.inserted_length - 0.005, wire.rotation_angle);
        command(follow_, vel, 0.0, 0.0);
        return stage(PairStage::kPark, "wire into the catheter, past the ostium of " + branch.name);
      }
      // Both advance, the wire 1 cm ahead, its tip turned away from other ostia.
      const Aim aim = aimFor(model, *data, lead_, path);
      const double turn =
          aim.wanted && !aim.toward_path ? tipBendAngle(model, *data, lead_, aim.direction) : 0.0;
      const std::vector<int> cath_path = atlas.path(cath_at.vessel, target_);
      const Aim cath_aim = aimFor(model, *data, follow_, cath_path);
      const double cath_turn = cath_aim.wanted && !cath_aim.toward_path
                                   ? tipBendAngle(model, *data, follow_, cath_aim.direction)
                                   : 0.0;
      command(lead_, vel, options_.advance_speed, options_.rotation_gain * turn);
      command(follow_, pos, wire.inserted_length - 0.01,
              cath.rotation_angle + options_.rotation_gain * options_.control_period * cath_turn);
      return stage(PairStage::kLead, "wire leads, catheter follows toward " + branch.name);
    }
    case PairStage::kBackOut: {
      if (wire.inserted_length > retract_until_) {
        command(lead_, vel, -options_.retract_speed, 0.0);
        command(follow_, pos, wire.inserted_length - 0.01, cath.rotation_angle);
        return "";
      }
      return stage(PairStage::kLead, "advance again");
    }
    case PairStage::kPark: {
      command(lead_, pos, cath.inserted_length - 0.005, wire.rotation_angle);
      command(follow_, vel, 0.0, 0.0);
      if (wire.inserted_length > cath.inserted_length - 0.004) return "";
      return stage(PairStage::kEngage, "turn the catheter's tip toward " + branch.name);
    }
    case PairStage::kEngage: {
      if (cath_past < -(branch.radius + 0.01)) {  // pulled back past it: advance and try again
        if (++report_.retries > options_.max_retries) {
          fail("retries exhausted (" + std::to_string(options_.max_retries) +
                   "): the catheter does not engage " + branch.name,
               t);
          return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
        }
        return stage(PairStage::kLead, "missed the ostium of " + branch.name + "; advance again");
      }
      if (std::find(plan.begin(), plan.end(), cath_at.vessel) == plan.end()) {
        // The catheter took the sibling: back out of it, and again.
        if (++report_.retries > options_.max_retries) {
          fail("retries exhausted (" + std::to_string(options_.max_retries) +
                   "): the catheter does not engage " + branch.name,
               t);
          return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
        }
        retract_until_ = std::max(0.0, wire.inserted_length - cath_at.depth - 0.015);
        return stage(PairStage::kBackOut,
                     "catheter in " + atlas.vessels()[cath_at.vessel].name + "; back out");
      }
      const double turn = tipBendAngle(model, *data, follow_, take);
      const bool aimed = std::abs(turn) < options_.aim_tolerance;
      const bool terminal =
          branch.origin_depth >= host.length - 1e-4 || branch.origin_depth <= 1e-4;
      // Engage: pull back onto a side branch's ostium; advance into a
      // bifurcation's branch.
      const double speed = !aimed     ? 0.0
                           : terminal ? 0.5 * options_.advance_speed
                                      : -0.5 * options_.retract_speed;
      command(follow_, vel, speed, options_.rotation_gain * turn);
      command(lead_, pos, cath.inserted_length - 0.005, wire.rotation_angle);
      return stage(PairStage::kEngage, "");
    }
    case PairStage::kWireIn: {
      command(follow_, vel, 0.0, 0.0);
      const bool deep = !wire_off_plan && ((wire_at.vessel == branch_ && wire_at.depth > 0.02) ||
                                           std::find(plan.begin(), plan.end(), wire_at.vessel) >
                                               std::find(plan.begin(), plan.end(), branch_));
      if (deep) {
        progress_time_ = t;
        return stage(PairStage::kFollow, "wire in " + branch.name + "; catheter follows");
      }
      if (wire_off_plan || wire.inserted_length > cath.inserted_length + 0.06) {
        // The wire went elsewhere: back into the catheter, engage again.
        if (++report_.retries > options_.max_retries) {
          fail("retries exhausted (" + std::to_string(options_.max_retries) + ")", t);
          return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
        }
        command(lead_, pos, cath.inserted_length - 0.005, wire.rotation_angle);
        return stage(PairStage::kPark, "the wire missed " + branch.name + "; back in");
      }
      // The wire's bent tip out of the catheter, toward the branch.
      const Vec3 want = take;
      command(lead_, vel, 0.5 * options_.advance_speed,
              options_.rotation_gain * tipBendAngle(model, *data, lead_, want));
      return "";
    }
    case PairStage::kFollow: {
      // The catheter over the wire into the branch, its tip 2 cm behind the wire's.
      const VesselLocation in_branch = atlas.locateIn(branch_, cath.position.back());
      const bool followed = cath_at.vessel == branch_ && in_branch.depth > host.radius + 0.01;
      if (wire_at.vessel == target_ && wire_at.depth >= options_.depth) {
        stage_ = PairStage::kOver;
        best_remaining_ = 1e9;
        return "t=" + std::to_string(t) + " s  the wire is in the target";
      }
      if (followed || t - progress_time_ > options_.stuck_time) {
        progress_time_ = t;
        best_remaining_ = 1e9;
        return stage(PairStage::kLead, "catheter in " + atlas.vessels()[cath_at.vessel].name);
      }
      // The wire holds in the target's own branch (its dwell is judged);
      // toward a deeper target it goes on slowly, steered away from other
      // ostia, so that the catheter can follow it past the ostium.
      double advance = 0.0, turn = 0.0;
      if (branch_ != target_) {
        const Aim aim = aimFor(model, *data, lead_, path);
        turn = aim.wanted ? tipBendAngle(model, *data, lead_, aim.direction) : 0.0;
        advance = aim.wanted && aim.toward_path && std::abs(turn) > options_.aim_tolerance
                      ? 0.0
                      : 0.5 * options_.advance_speed;
      }
      command(lead_, vel, advance, options_.rotation_gain * turn);
      command(follow_, pos, wire.inserted_length - 0.02, cath.rotation_angle);
      if (wire_off_plan) return stage(PairStage::kLead, "");
      return "";
    }
    case PairStage::kOver:
      break;
  }
  return "";
}

void Autopilot::observe(const SimData& data, bool step_failed) {
  if (step_failed) ++report_.failed_steps;
  for (const Contact& c : data.contacts)
    if (c.other_device < 0 && !c.lumen)  // the vessel wall, not a device's lumen
      report_.peak_wall_force = std::max(report_.peak_wall_force, c.force);
}

}  // namespace evsim
