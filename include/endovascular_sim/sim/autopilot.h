// A navigation baseline: drives insertion and rotation of a device (or a
// guidewire inside a catheter) to a named vessel using only what a
// clinician sees on the screen: the devices' shapes and the vessels'
// centrelines, never the contact forces.
//
// It plans the vessels from the tip to the target (VesselAtlas::path). At
// every control tick it turns the bent tip towards the next vessel of the
// path as the tip nears its ostium, and away from the ostia of vessels off
// the path; it advances when aimed, pulls back past the junction and tries
// again when the tip has entered a wrong vessel or has slid past the ostium,
// and lets the outer device (a catheter) follow the inner one at a fixed
// lag. It stops when the tip has been `depth` inside the target for `dwell`
// seconds, or ends "not reached" with the reason (retries exhausted, stuck,
// out of time).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "endovascular_sim/sim/simulation.h"
#include "endovascular_sim/sim/targets.h"

namespace evsim {

struct AutopilotOptions {
  double control_period{0.02};     // [s] between decisions
  double advance_speed{0.03};      // [m/s] insertion while aimed
  double retract_speed{0.03};      // [m/s]
  double rotation_gain{4.0};       // proximal rotation speed per radian of aim error [1/s]
  double aim_tolerance{0.45};      // [rad] aim error below which it advances near an ostium
  double approach_distance{0.02};  // [m] beyond the parent's radius: aiming starts there
  double follow_lag{0.03};         // [m] the outer device's tip stays this far behind the inner's
  double outer_fit{1.3};    // the outer device goes into a vessel at least this many of its radii
                            // in radius (beyond, the inner device goes on alone)
  double depth{0.02};       // [m] inside the target: reached (with dwell; requiredDepth)
  double dwell{0.5};        // [s]
  double probe_after{1.0};  // [s] turning toward a branch without the tip following: then ...
  double probe_pace{0.25};  // ... it advances at this fraction of its speed while it turns
  int max_retries{12};
  double stuck_time{3.0};  // [s] without progress along the path: pull back, retry
  double timeout{90.0};    // [s] of simulated time
};

/// Length [m] of a device's last section: its shaped tip (a J, an angle,
/// a catheter's curve), which the autopilot turns toward where it goes.
double shapedLength(const DeviceModel& m);

/// Whether a tip at `tip` [m], located in `vessel`, is off `plan`: in a
/// vessel not on it, and in no lumen of the plan's (past a bifurcation both
/// daughters' lumens hold the first millimetres).
bool offPlan(const VesselAtlas& atlas, const std::vector<int>& plan, int vessel, const Vec3& tip);

/// Whether `vessel` continues its parent rather than branching off it: it
/// starts at the parent's end, keeps 70 % of the parent's radius, every
/// other daughter there is under two thirds of its own, and it goes on
/// within 60 degrees of the parent's direction (the aorta past an
/// ostium where a segmentation splits it). The catheter does not engage it.
bool isContinuation(const VesselAtlas& atlas, int vessel);

enum class AutopilotPhase { kAdvance, kAim, kRetract, kDwell, kReached, kFailed };
const char* phaseName(AutopilotPhase phase);

/// A summary: what `evsim navigate` prints and the NavigateTo action returns.
struct AutopilotReport {
  bool reached{false};
  std::string reason;  // why not reached ("" when reached)
  double time{0.0};    // [s] simulated, from the start of the run
  int retries{0};
  double peak_wall_force{0.0};  // [N] the largest contact force on the vessel wall
  long failed_steps{0};
  double remaining_path{0.0};  // [m] along the centrelines, at the end
};

class Autopilot {
 public:
  /// Throws LoadError (naming the scene file and what exists) for an unknown
  /// target, one not connected to the device's access point, one narrower
  /// than the device, or a scene without vessels. `device` names the device
  /// that must reach it ("": the innermost device of the first chain).
  Autopilot(const SceneModel& model, const SimData& data, const std::string& target,
            const std::string& device = "", const AutopilotOptions& options = {});

  /// Sets the drive commands for the next steps; call before every step.
  /// Returns a line when the phase changes ("" otherwise).
  std::string control(const SceneModel& model, SimData* data);
  /// After every step: its outcome (failed steps and forces are counted).
  void observe(const SimData& data, bool step_failed);

  bool done() const {
    return phase_ == AutopilotPhase::kReached || phase_ == AutopilotPhase::kFailed;
  }
  AutopilotPhase phase() const { return phase_; }
  const AutopilotReport& report() const { return report_; }
  int target() const { return target_; }
  int device() const { return lead_; }
  /// The vessel the lead tip is in, and the path length left to the target [m].
  int currentVessel() const { return current_vessel_; }
  double remainingPath() const { return report_.remaining_path; }

 private:
  struct Aim {
    bool wanted{false};
    Vec3 direction{Vec3::Zero()};  // where the bent tip should point
    double distance{0.0};          // [m] from the tip to the ostium that asks it
    bool toward_path{false};       // the ostium is the next vessel of the path
    bool toward_parent{false};     // ... the parent, its course back from a fork of daughters
  };
  /// Where a device's bent tip should point: toward the next vessel of
  /// `path` (from its tip) near its ostium, away from other ostia near them.
  Aim aimFor(const SceneModel& model, const SimData& data, int device,
             const std::vector<int>& path) const;
  /// Rotation [rad] about the shaft that turns a device's bent tip toward `want`.
  double tipBendAngle(const SceneModel& model, const SimData& data, int device,
                      const Vec3& want) const;
  /// The rotation [rad] that turns the tip toward a branch of the path,
  /// offset on each retry (0, then +-0.6, +-1.2 rad and a half turn about
  /// the aim): the tip that did not take the branch aimed is turned a
  /// little either way, as a hand searches for an ostium.
  double searchTurn(double turn) const;
  /// The fraction of its speed a tip advances at while `turning` toward a
  /// branch: none at first, probe_pace after probe_after seconds (a tip
  /// held by the wall turns only as it moves), all when aimed.
  double turningPace(bool turning, double t);
  /// The catheter technique for a wire inside a catheter, up to the first
  /// branch of the plan: the wire leads around the curve with the catheter
  /// behind it; past the branch's ostium the wire is drawn into the
  /// catheter, the catheter's shaped tip is turned toward the ostium and
  /// pulled back until it engages; the wire is advanced into the branch.
  /// Then (stage kOver) control() steers the wire with the catheter following.
  std::string controlPair(const SceneModel& model, SimData* data, const std::vector<int>& path,
                          double t);
  // The pair technique's parts (sim/autopilot_pair.cpp).
  struct PairView;  // what the screen shows of the pair at the branch it engages
  /// The branch of `plan` the catheter engages next (host_, branch_); false
  /// when none is left or it is too narrow for the catheter.
  bool choosePairBranch(const SceneModel& model, const SimData& data, const std::vector<int>& plan);
  /// How far [m] before a bifurcation the wire is drawn into the catheter.
  double parkBefore(const PairView& v) const;
  std::string leadStage(const PairView& v);
  std::string backOutStage(const PairView& v);
  std::string parkStage(const PairView& v);
  std::string engageStage(const PairView& v);
  std::string wireInStage(const PairView& v);
  std::string followStage(const PairView& v);
  static void command(const SceneModel& model, SimData* data, int device, DriveCommand::Mode mode,
                      double insertion, double rotation);
  enum class PairStage;
  /// Moves to stage `next`: its line ("" when already there).
  std::string stageTo(PairStage next, const std::string& what, double t);
  /// Counts a retry; past the limit fails (reason "retries exhausted (N)`why`")
  /// and returns the failure's line, else "".
  std::string retryOrFail(const std::string& why, double t);
  std::string setPhase(AutopilotPhase phase, const std::string& why, double t);
  /// Judges the target's depth and dwell at the data's time: true once reached.
  bool judgeDwell(const SceneModel& model, const SimData& data);
  /// The lead device alone (or with its outer device trailing): the dwell in
  /// the target, a pull back and retry, or a turn toward the path's next
  /// vessel and an advance.
  std::string steerLead(const SceneModel& model, SimData* data, const std::vector<int>& plan,
                        const std::vector<int>& path, const VesselLocation& at, double remaining);
  /// Why the tip must be pulled back and the approach repeated (a wrong
  /// vessel, slid past the ostium, no progress), and *pull [m]; "" if not.
  std::string retryWhy(const VesselAtlas& atlas, const std::vector<int>& plan,
                       const std::vector<int>& path, const VesselLocation& at, const Vec3& tip,
                       double remaining, double t, double* pull) const;
  /// The inserted length [m] a retry pulls the lead back to: `inserted`,
  /// but never below half its length at the start (a retry that would pull
  /// the devices out of the body tries again from there).
  double retractFloor(double inserted) const;
  void drive(const SceneModel& model, SimData* data, double insertion_speed, double rotation);
  void fail(const std::string& why, double t);

  AutopilotOptions options_;
  int target_{-1};
  double goal_depth_{0.0};  // [m] requiredDepth of the target for options_.depth
  int lead_{-1};            // device whose tip must reach the target
  int follow_{-1};          // its outer device (-1: none)
  int entry_vessel_{-1};
  AutopilotPhase phase_{AutopilotPhase::kAdvance};
  AutopilotReport report_;
  double start_time_{0.0};
  double start_inserted_{0.0};  // [m] the lead's inserted length at the start
  double next_tick_{0.0};
  double retract_until_{0.0};  // [m] inserted length to pull back to
  double best_remaining_{1e9};
  double progress_time_{0.0};
  std::vector<TargetProgress> goal_progress_;  // the target's dwell, judged every step
  int current_vessel_{-1};
  double last_turn_{0.0};       // [rad] the last aim error, for its sign near a half turn
  double turning_since_{-1.0};  // [s] when the tip began turning toward a branch (-1: aimed)
  enum class PairStage { kLead, kBackOut, kPark, kEngage, kWireIn, kFollow, kOver };  // NOLINT
  PairStage stage_{PairStage::kLead};
  double stage_since_{0.0};     // [s] when the pair entered its stage
  int host_{-1}, branch_{-1};   // the vessel the catheter engages from, and the branch
  bool catheter_leads_{false};  // the wire missed the bifurcation's branch: the catheter leads
  bool wire_selects_{false};    // the catheter did not engage the branch: the wire steers into it
  double travel_{1.0};          // direction of travel along the host (+1: away from its origin)
};

/// Runs the autopilot headless from `data` until it ends, as `evsim
/// navigate` does: a step the scene's options cannot solve is tried once
/// more with the recovery options (stepOrRecover); a step that fails even
/// so ends the run (counted in failed_steps). `on_line` gets each phase line
/// and each recovery; `on_step` the data after each step. Throws LoadError
/// for a target the autopilot refuses.
AutopilotReport runAutopilot(const SceneModel& model, SimData* data, const std::string& target,
                             const std::string& device = "", const AutopilotOptions& options = {},
                             const std::function<void(const std::string&)>& on_line = {},
                             const std::function<void(const SimData&)>& on_step = {});

}  // namespace evsim
