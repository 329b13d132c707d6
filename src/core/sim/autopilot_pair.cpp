// The autopilot's catheter technique for a guidewire inside a catheter
// (sim/autopilot.h): which branch of the plan the catheter engages next,
// what the screen shows of the pair there, and one function per stage:
// lead, back out, park the wire, engage the catheter, wire in, follow.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "endovascular_sim/sim/autopilot.h"

namespace evsim {

namespace {
constexpr double kTerminalEngageDepth = 0.01;  // [m] see controlPair

/// Whether a vessel starts at an end of its parent (a bifurcation's
/// branch), not from its side.
bool isTerminalBranch(const VesselAtlas& atlas, int vessel) {
  const NamedVessel& v = atlas.vessels()[vessel];
  if (v.parent < 0) return false;
  return v.origin_depth >= atlas.vessels()[v.parent].length - 1e-4 || v.origin_depth <= 1e-4;
}
}  // namespace

bool isContinuation(const VesselAtlas& atlas, int vessel) {
  const NamedVessel& v = atlas.vessels()[vessel];
  if (v.parent < 0) return false;
  const NamedVessel& parent = atlas.vessels()[v.parent];
  if (v.origin_depth < parent.length - 1e-4) return false;  // from the parent's side
  // The parent's calibre goes on in it, and every other daughter there is a
  // side branch (under two thirds of its radius): not a bifurcation of
  // peers, as the trunk's into the subclavian and the carotid.
  if (v.radius < 0.7 * parent.radius) return false;
  for (int sibling : parent.children) {
    const NamedVessel& s = atlas.vessels()[sibling];
    if (sibling != vessel && s.origin_depth >= parent.length - 1e-4 &&
        s.radius > (2.0 / 3.0) * v.radius)
      return false;
  }
  // And it goes on the way the parent went (within 60 degrees).
  Vec3 end_dir, start_dir;
  atlas.pointAt(v.parent, parent.length, &end_dir);
  const Vec3 start = atlas.pointAt(vessel, 0.0);
  const Vec3 ahead = atlas.pointAt(vessel, std::min(v.length, 2.0 * parent.radius));
  start_dir = (ahead - start).normalized();
  return end_dir.dot(start_dir) > 0.5;
}

/// What the screen shows of the pair at the branch it engages.
struct Autopilot::PairView {
  const SceneModel& model;
  SimData* data;
  const std::vector<int>& path;
  std::vector<int> plan;
  double t;
  const NamedVessel& branch;
  const NamedVessel& host;
  const DeviceState& wire;
  const DeviceState& cath;
  VesselLocation wire_at, cath_at;
  double cath_past{-1.0};  // [m] the catheter's tip past the branch's ostium along the host
  bool wire_off_plan{false};
  Vec3 out{Vec3::Zero()};       // the branch's direction out of the host
  Vec3 cath_dir{Vec3::Zero()};  // the catheter tip's
  Vec3 take{Vec3::Zero()};      // where a bent tip should point to take the branch
  bool terminal{false};         // the host ends in the bifurcation
  bool onPlan(int vessel) const {
    return std::find(plan.begin(), plan.end(), vessel) != plan.end();
  }
  /// Whether `vessel` is on the plan beyond `branch` (a vessel off the
  /// plan is not, wherever its lumen lies).
  bool beyond(int vessel, int branch) const {
    const auto at = std::find(plan.begin(), plan.end(), vessel);
    return at != plan.end() && at > std::find(plan.begin(), plan.end(), branch);
  }
};

bool Autopilot::choosePairBranch(const SceneModel& model, const SimData& data,
                                 const std::vector<int>& plan) {
  const VesselAtlas& atlas = *model.atlas;
  // The next turn of the plan into a branch, from the catheter's vessel on.
  const auto cath_on_plan = std::find(plan.begin(), plan.end(), data.tips[follow_].vessel);
  // A catheter that has entered a bifurcation's branch it engages (its tip
  // not yet 1 cm along it: controlPair) still engages it: the wire goes in
  // next, whatever follows. (A side branch's ostium entered, the pair goes
  // on to the next turn: the catheter is where it needs to be.)
  const bool engaging =
      stage_ == PairStage::kPark || stage_ == PairStage::kEngage || stage_ == PairStage::kWireIn;
  if (engaging && branch_ >= 0 && isTerminalBranch(atlas, branch_) && cath_on_plan != plan.end() &&
      cath_on_plan >= std::find(plan.begin(), plan.end(), branch_))
    return true;
  if (cath_on_plan != plan.end()) {
    const size_t from_index = static_cast<size_t>(cath_on_plan - plan.begin());
    int host = -1, branch = -1;
    for (size_t i = from_index; i + 1 < plan.size() && branch < 0; ++i)
      if (atlas.vessels()[plan[i + 1]].parent == plan[i] && !isContinuation(atlas, plan[i + 1])) {
        host = plan[i];
        branch = plan[i + 1];
        const double from = i == from_index ? data.tips[follow_].depth
                            : atlas.vessels()[plan[i - 1]].parent == host
                                ? atlas.vessels()[plan[i - 1]].origin_depth
                                : 0.0;
        // Toward the ostium; from a sibling at the host's end (the tree
        // rooted upstream of the access: a patient's file rooted at the
        // aortic root), away from that end.
        const double ostium = atlas.vessels()[branch].origin_depth;
        const bool from_end = i > from_index && std::abs(ostium - from) < 1e-6 &&
                              ostium >= atlas.vessels()[host].length - 1e-4;
        if (branch != branch_) travel_ = !from_end && ostium >= from ? 1.0 : -1.0;
      }
    // The catheter is in the target, no turn is left, or the next branch is
    // too narrow for the catheter (less than outer_fit times its radius): the wire
    // goes on alone, the catheter trailing where it fits.
    if (branch < 0 || atlas.vessels()[branch].radius <
                          options_.outer_fit * model.devices[follow_].node_radius.back())
      return false;
    if (branch != branch_ && stage_ != PairStage::kLead) stage_ = PairStage::kLead;
    if (branch != branch_) catheter_leads_ = wire_selects_ = false;
    host_ = host;
    branch_ = branch;
  }
  return branch_ >= 0;
}

std::string Autopilot::controlPair(const SceneModel& model, SimData* data,
                                   const std::vector<int>& path, double t) {
  const VesselAtlas& atlas = *model.atlas;
  std::vector<int> plan = atlas.path(entry_vessel_, target_);
  if (!choosePairBranch(model, *data, plan)) {
    stage_ = PairStage::kOver;
    return "";
  }
  // A catheter inserted to its full length goes no deeper: the wire goes on
  // alone from there.
  if (data->devices[follow_].inserted_length >= model.devices[follow_].length - 0.002) {
    stage_ = PairStage::kOver;
    return "t=" + std::to_string(t) + " s  the catheter is fully inserted; the wire goes on";
  }
  PairView v{model,
             data,
             path,
             std::move(plan),
             t,
             atlas.vessels()[branch_],
             atlas.vessels()[host_],
             data->devices[lead_],
             data->devices[follow_],
             data->tips[lead_],
             data->tips[follow_]};
  // How far the catheter's tip is past the branch's ostium along the host.
  // (In a vessel branching off the host at the same junction: its depth.)
  // (In the vessel it came from, at that junction: before it by its depth.)
  if (v.cath_at.vessel == host_)
    v.cath_past = (v.cath_at.depth - v.branch.origin_depth) * travel_;
  else if (atlas.vessels()[v.cath_at.vessel].parent == host_ &&
           std::abs(atlas.vessels()[v.cath_at.vessel].origin_depth - v.branch.origin_depth) < 1e-6)
    v.cath_past = v.beyond(host_, v.cath_at.vessel) ? -v.cath_at.depth : v.cath_at.depth;
  v.wire_off_plan = offPlan(atlas, v.plan, v.wire_at.vessel, v.wire.position.back());
  v.out = (atlas.pointAt(branch_, std::min(v.branch.length, 1.5 * v.host.radius + 0.005)) -
           atlas.pointAt(branch_, 0.0))
              .normalized();
  const int cn = model.devices[follow_].num_nodes;
  v.cath_dir = (v.cath.position[cn - 1] - v.cath.position[cn - 3]).normalized();
  // Where a bent tip should point to take the branch: toward it, or, where
  // it runs nearly straight on (within 35 degrees of the catheter's tip),
  // away from its sibling: a bent tip pointed ahead turns aside.
  v.take = v.out;
  if (v.cath_dir.dot(v.out) > std::cos(35.0 * M_PI / 180.0))
    for (int sibling : v.host.children) {
      const NamedVessel& o = atlas.vessels()[sibling];
      if (sibling == branch_ || std::abs(o.origin_depth - v.branch.origin_depth) > v.host.radius)
        continue;
      v.take = -(atlas.pointAt(sibling, std::min(o.length, 1.5 * v.host.radius + 0.005)) -
                 atlas.pointAt(sibling, 0.0))
                    .normalized();
    }
  v.terminal = isTerminalBranch(atlas, branch_);
  const VesselLocation cath_in_branch = atlas.locateIn(branch_, v.cath.position.back());
  // Into a bifurcation's branch the catheter goes 1 cm deep before the wire
  // comes out: at its ostium the wire would fall back into the sibling.
  const bool engaged =
      (v.terminal ? cath_in_branch.inside && cath_in_branch.depth >= kTerminalEngageDepth
                  : v.cath_at.vessel == branch_ ||
                        (cath_in_branch.inside && cath_in_branch.depth >= 0.6 * v.host.radius)) &&
      v.cath_dir.dot(v.out) > 0.5;
  if (engaged && (stage_ == PairStage::kLead || stage_ == PairStage::kEngage)) {
    command(model, data, follow_, DriveCommand::Mode::kVelocity, 0.0, 0.0);
    return stageTo(PairStage::kWireIn, "catheter engaged in " + v.branch.name + "; wire in", t);
  }
  switch (stage_) {
    case PairStage::kLead:
      return leadStage(v);
    case PairStage::kBackOut:
      return backOutStage(v);
    case PairStage::kPark:
      return parkStage(v);
    case PairStage::kEngage:
      return engageStage(v);
    case PairStage::kWireIn:
      return wireInStage(v);
    case PairStage::kFollow:
      return followStage(v);
    case PairStage::kOver:
      break;
  }
  return "";
}

void Autopilot::command(const SceneModel& model, SimData* data, int device, DriveCommand::Mode mode,
                        double insertion, double rotation) {
  DriveCommand c;
  c.mode = mode;
  const DeviceModel& m = model.devices[device];
  c.insertion = mode == DriveCommand::Mode::kPosition
                    ? std::clamp(insertion, 0.0, m.length)
                    : std::clamp(insertion, -m.max_insertion_speed, m.max_insertion_speed);
  c.rotation = mode == DriveCommand::Mode::kPosition
                   ? rotation
                   : std::clamp(rotation, -m.max_rotation_speed, m.max_rotation_speed);
  applyCommand(data, device, c);
}

std::string Autopilot::stageTo(PairStage next, const std::string& what, double t) {
  if (next == stage_) return std::string();
  stage_ = next;
  stage_since_ = t;
  std::ostringstream line;
  line << "t=" << t << " s  " << what;
  return line.str();
}

std::string Autopilot::retryOrFail(const std::string& why, double t) {
  if (++report_.retries <= options_.max_retries) return "";
  fail("retries exhausted (" + std::to_string(options_.max_retries) + ")" + why, t);
  return "t=" + std::to_string(t) + " s  failed: " + report_.reason;
}

namespace {
constexpr auto kPos = DriveCommand::Mode::kPosition;
constexpr auto kVel = DriveCommand::Mode::kVelocity;
}  // namespace

double Autopilot::parkBefore(const PairView& v) const {
  // (With the catheter leading, the wire 1 cm ahead of it is drawn in
  // before its tip reaches the fork.)
  return v.host.radius + 0.003 + (catheter_leads_ ? 0.012 : 0.0);
}

std::string Autopilot::leadStage(const PairView& v) {
  const VesselAtlas& atlas = *v.model.atlas;
  // The wire in the branch, 1 cm deep (or half the branch) before the
  // catheter follows: at the ostium of a bifurcation's branch its tip,
  // pushed on by the catheter, slips into the sibling.
  const double held_depth = std::min(kTerminalEngageDepth, 0.5 * v.branch.length);
  if (!v.wire_off_plan && (v.beyond(v.wire_at.vessel, branch_) ||
                           (v.wire_at.vessel == branch_ && v.wire_at.depth >= held_depth))) {
    progress_time_ = v.t;
    return stageTo(PairStage::kFollow, "the wire is in " + v.branch.name + "; catheter follows",
                   v.t);
  }
  if (v.wire_off_plan) {  // into a wrong vessel: both back out of it
    const std::string failed = retryOrFail("", v.t);
    if (!failed.empty()) return failed;
    // At a bifurcation the catheter's shaped tip leads next: the wire is
    // drawn into it before the fork, the catheter engages the branch.
    catheter_leads_ = v.terminal;
    retract_until_ = retractFloor(v.wire.inserted_length - v.wire_at.depth - v.host.radius - 0.01);
    return stageTo(PairStage::kBackOut, "back out of " + atlas.vessels()[v.wire_at.vessel].name,
                   v.t);
  }
  // (A wire already in the branch goes on: the catheter follows it there.)
  if (v.wire_at.vessel != branch_ &&
      (v.terminal ? v.cath_past > -parkBefore(v) : v.cath_past > v.branch.radius + 0.005)) {
    command(v.model, v.data, lead_, kPos, v.cath.inserted_length - 0.005, v.wire.rotation_angle);
    command(v.model, v.data, follow_, kVel, 0.0, 0.0);
    return stageTo(PairStage::kPark, "wire into the catheter, past the ostium of " + v.branch.name,
                   v.t);
  }
  // Both advance, the wire 1 cm ahead, its tip turned away from other
  // ostia, and at a bifurcation toward the plan's daughter.
  const Aim aim = aimFor(v.model, *v.data, lead_, v.path);
  // (Toward a side branch the wire steers once the catheter failed to
  // engage it: its angled tip may take the branch, the catheter following.)
  const bool steer =
      aim.wanted && (!aim.toward_path || isTerminalBranch(atlas, v.path[1]) || wire_selects_);
  double turn = steer ? tipBendAngle(v.model, *v.data, lead_, aim.direction) : 0.0;
  if (steer && aim.toward_path) turn = searchTurn(turn);
  const std::vector<int> cath_path = atlas.path(v.cath_at.vessel, target_);
  const Aim cath_aim = aimFor(v.model, *v.data, follow_, cath_path);
  double cath_turn = cath_aim.wanted && !cath_aim.toward_path
                         ? tipBendAngle(v.model, *v.data, follow_, cath_aim.direction)
                         : 0.0;
  // At a fork of daughters met from one of them (up the descending aorta to
  // the subclavian's ostium) the parent's course runs nearly along the
  // shafts: no bend can be aimed at it. After a miss both tips are turned
  // together by an eighth of a turn more at each retry, as a hand searches,
  // until the pair takes the parent.
  if (aim.toward_parent && report_.retries > 0) {
    const double hand = report_.retries * 0.25 * M_PI;
    turn = std::remainder(hand - v.wire.rotation_angle, 2 * M_PI);
    cath_turn = std::remainder(hand - v.cath.rotation_angle, 2 * M_PI);
  }
  // Near a bifurcation's branch of the path: turn first, then advance.
  const bool hold = steer && aim.toward_path && std::abs(turn) > options_.aim_tolerance;
  command(v.model, v.data, lead_, kVel, turningPace(hold, v.t) * options_.advance_speed,
          options_.rotation_gain * turn);
  command(v.model, v.data, follow_, kPos, v.wire.inserted_length - 0.01,
          v.cath.rotation_angle + options_.rotation_gain * options_.control_period * cath_turn);
  return stageTo(PairStage::kLead, "wire leads, catheter follows toward " + v.branch.name, v.t);
}

std::string Autopilot::backOutStage(const PairView& v) {
  if (v.wire.inserted_length > retract_until_) {
    command(v.model, v.data, lead_, kVel, -options_.retract_speed, 0.0);
    command(v.model, v.data, follow_, kPos, v.wire.inserted_length - 0.01, v.cath.rotation_angle);
    return "";
  }
  return stageTo(PairStage::kLead, "advance again", v.t);
}

std::string Autopilot::parkStage(const PairView& v) {
  command(v.model, v.data, lead_, kPos, v.cath.inserted_length - 0.005, v.wire.rotation_angle);
  command(v.model, v.data, follow_, kVel, 0.0, 0.0);
  if (v.wire.inserted_length > v.cath.inserted_length - 0.004) return "";
  return stageTo(PairStage::kEngage, "turn the catheter's tip toward " + v.branch.name, v.t);
}

std::string Autopilot::engageStage(const PairView& v) {
  const VesselAtlas& atlas = *v.model.atlas;
  const std::string not_engaged = ": the catheter does not engage " + v.branch.name;
  const double missed = v.terminal ? parkBefore(v) + 0.005 : v.branch.radius + 0.01;
  // However it fails (below), the wire tries the branch first next time.
  wire_selects_ |= v.cath_past < -missed || !v.onPlan(v.cath_at.vessel) ||
                   v.t - stage_since_ > 2.0 * options_.stuck_time;
  if (v.cath_past < -missed) {  // pulled back past it: advance and try again
    const std::string failed = retryOrFail(not_engaged, v.t);
    if (!failed.empty()) return failed;
    return stageTo(PairStage::kLead, "missed the ostium of " + v.branch.name + "; advance again",
                   v.t);
  }
  if (!v.onPlan(v.cath_at.vessel)) {  // the catheter took the sibling: back out, and again
    const std::string failed = retryOrFail(not_engaged, v.t);
    if (!failed.empty()) return failed;
    retract_until_ = retractFloor(v.wire.inserted_length - v.cath_at.depth - 0.015);
    return stageTo(PairStage::kBackOut,
                   "catheter in " + atlas.vessels()[v.cath_at.vessel].name + "; back out", v.t);
  }
  if (v.t - stage_since_ > 2.0 * options_.stuck_time) {
    // No engagement: both back until the wire's tip is 1.5 cm before the
    // ostium, and the wire leads toward it again (wire_selects_).
    const std::string failed = retryOrFail(not_engaged, v.t);
    if (!failed.empty()) return failed;
    retract_until_ = retractFloor(v.wire.inserted_length - std::max(0.0, v.cath_past) - 0.015);
    return stageTo(PairStage::kBackOut,
                   "the catheter does not engage " + v.branch.name + "; the wire tries it", v.t);
  }
  const double turn = tipBendAngle(v.model, *v.data, follow_, v.take);
  const bool aimed = std::abs(turn) < options_.aim_tolerance;
  // Engage: pull back onto a side branch's ostium; advance into a
  // bifurcation's branch. A tip that does not turn within a second (held
  // by the wall) is moved that way slowly while it turns.
  const bool probing = !aimed && v.t - stage_since_ > 1.0;
  const double pace = aimed ? 0.5 : probing ? 0.25 : 0.0;
  const double speed = v.terminal ? pace * options_.advance_speed : -pace * options_.retract_speed;
  command(v.model, v.data, follow_, kVel, speed, options_.rotation_gain * turn);
  command(v.model, v.data, lead_, kPos, v.cath.inserted_length - 0.005, v.wire.rotation_angle);
  return stageTo(PairStage::kEngage, "", v.t);
}

std::string Autopilot::wireInStage(const PairView& v) {
  // Forward pressure on the catheter while the wire comes out of it into a
  // bifurcation's branch: its curve, straightened by the wire, would back
  // its tip out of the branch.
  const VesselLocation cath_in_branch = v.model.atlas->locateIn(branch_, v.cath.position.back());
  const bool hold_in = v.terminal && cath_in_branch.depth < kTerminalEngageDepth + 0.005;
  command(v.model, v.data, follow_, kVel, hold_in ? 0.3 * options_.advance_speed : 0.0, 0.0);
  const bool deep = !v.wire_off_plan && ((v.wire_at.vessel == branch_ && v.wire_at.depth > 0.02) ||
                                         v.beyond(v.wire_at.vessel, branch_));
  if (deep) {
    progress_time_ = v.t;
    return stageTo(PairStage::kFollow, "wire in " + v.branch.name + "; catheter follows", v.t);
  }
  if (v.wire_off_plan || v.wire.inserted_length > v.cath.inserted_length + 0.06) {
    // The wire went elsewhere: back into the catheter, engage again.
    const std::string failed = retryOrFail("", v.t);
    if (!failed.empty()) return failed;
    command(v.model, v.data, lead_, kPos, v.cath.inserted_length - 0.005, v.wire.rotation_angle);
    return stageTo(PairStage::kPark, "the wire missed " + v.branch.name + "; back in", v.t);
  }
  // The wire's bent tip out of the catheter, toward the branch; once in a
  // short branch, toward the plan's next vessel at its far end (as in
  // steerLead: turned first, then advanced).
  // (Held while it turns only once its shaped tip is out of the catheter;
  // each retry turns it a little aside, searchTurn.)
  Vec3 want = v.take;
  bool toward_next = false;
  if (v.wire_at.vessel == branch_) {
    const Aim aim = aimFor(v.model, *v.data, lead_, v.path);
    if (aim.wanted) want = aim.direction;
    const double tip_out = v.wire.inserted_length - v.cath.inserted_length;
    toward_next =
        aim.wanted && aim.toward_path && tip_out > shapedLength(v.model.devices[lead_]) + 0.002;
  }
  const double turn = searchTurn(tipBendAngle(v.model, *v.data, lead_, want));
  const bool hold = toward_next && std::abs(turn) > options_.aim_tolerance;
  command(v.model, v.data, lead_, kVel, turningPace(hold, v.t) * 0.5 * options_.advance_speed,
          options_.rotation_gain * turn);
  return "";
}

std::string Autopilot::followStage(const PairView& v) {
  const VesselAtlas& atlas = *v.model.atlas;
  // The catheter over the wire into the branch, its tip 2 cm behind the wire's.
  const VesselLocation in_branch = atlas.locateIn(branch_, v.cath.position.back());
  const bool followed = v.cath_at.vessel == branch_ && in_branch.depth > v.host.radius + 0.01;
  if (v.wire_at.vessel == target_ && v.wire_at.depth >= goal_depth_) {
    stage_ = PairStage::kOver;
    best_remaining_ = 1e9;
    return "t=" + std::to_string(v.t) + " s  the wire is in the target";
  }
  if (followed) {
    progress_time_ = v.t;
    best_remaining_ = 1e9;
    return stageTo(PairStage::kLead, "catheter in " + atlas.vessels()[v.cath_at.vessel].name, v.t);
  }
  if (v.t - progress_time_ > options_.stuck_time) {
    // The catheter does not follow into the branch: the wire goes on alone,
    // the catheter trailing it where it fits (drive()).
    progress_time_ = v.t;
    best_remaining_ = 1e9;
    stage_ = PairStage::kOver;
    return "t=" + std::to_string(v.t) + " s  the catheter does not follow into " + v.branch.name +
           "; the wire goes on";
  }
  // The wire holds in the target's own branch (its dwell is judged);
  // toward a deeper target it goes on slowly, steered away from other
  // ostia, so that the catheter can follow it past the ostium.
  double advance = 0.0, turn = 0.0;
  if (branch_ != target_) {
    const Aim aim = aimFor(v.model, *v.data, lead_, v.path);
    turn = aim.wanted ? tipBendAngle(v.model, *v.data, lead_, aim.direction) : 0.0;
    advance =
        turningPace(aim.wanted && aim.toward_path && std::abs(turn) > options_.aim_tolerance, v.t) *
        0.5 * options_.advance_speed;
  }
  command(v.model, v.data, lead_, kVel, advance, options_.rotation_gain * turn);
  // (never drawn back to the lag: the wire's support would move, and its
  // tip swing into the sibling)
  command(v.model, v.data, follow_, kPos,
          std::max(v.cath.inserted_length, v.wire.inserted_length - 0.02), v.cath.rotation_angle);
  if (v.wire_off_plan) return stageTo(PairStage::kLead, "", v.t);
  return "";
}

}  // namespace evsim
