// The simulation: an immutable SceneModel built once per scene, the SimData
// workspace it steps, and step() — the pipeline of the paper:
//
//   apply commands     insertion / rotation targets -> held proximal nodes
//   move vessels       only with the effect 'vessel_motion'
//   free motion        A dq_f = f (A = M/dt^2 + D/dt + K, block LDL^T: ChainFactor)
//   contacts           detection, status method, activation loop
//                      (contact/contact_solver.h); not solved after N loops:
//   subdivide          redo the step as two halves, recursively
//   commit             positions, velocities, contacts, statistics
//   sleep              at rest for SleepOptions::steps steps: later steps
//                      only advance the clock until something wakes it
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/core/effect_set.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "endovascular_sim/mechanics/drive_wrench.h"
#include "endovascular_sim/mechanics/implicit_euler.h"
#include "endovascular_sim/mechanics/introducer.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/targets.h"

namespace evsim {

/// How often each effect's code ran since makeData (tests read them: an
/// effect that is off stays at zero).
struct EffectCounters {
  long gravity{0};             // free motions loaded with gravity
  long vessel_motion{0};       // motion snapshots of the vessels
  long device_contact{0};      // passes of device-pair detection
  long subdivision{0};         // steps halved
  long friction{0};            // frictional contact problems solved
  long coaxial{0};             // passes of lumen detection
  long blood_drag{0};          // free motions loaded with the blood's drag
  long vessel_deformation{0};  // steps of the vessel wall
};

struct SceneModel {
  std::string name;
  std::string file;
  double time_step{1e-3};  // [s]
  EffectSet effects;
  Vec3 gravity{0.0, 0.0, 0.0};                     // [m/s^2]; zero unless the effect is on
  std::shared_ptr<const VesselField> vessels;      // null: free space
  std::shared_ptr<const ImplicitSurface> surface;  // what contacts are solved against
  std::shared_ptr<const VesselAtlas> atlas;        // the named vessels (null: free space)
  std::shared_ptr<const Centerline> centerline;    // the vessels' skeleton (null: free space)
  std::shared_ptr<const VesselWall> wall;          // effect 'vessel_deformation' (else null)
  double wall_reach{0.0};  // [m] the most a centreline point moves or a radius widens
  std::string frame;       // the vessels' anatomical frame (geometry/patient_frame.h; "": unknown)
  std::vector<AneurysmSpec> aneurysms;  // the domes blended with the vessels
  std::vector<Target> targets;          // the scene's navigation targets
  XraySpec xray;                        // the scene's X-ray system (`xray:`)
  ContactOptions contact;
  SleepOptions sleep;                             // off with the effect 'vessel_motion'
  std::vector<std::vector<SamplePoint>> samples;  // contact sample points per device
  std::vector<DeviceModel> devices;
  std::vector<Introducer> introducers;
  std::vector<DriveSpec> drive_specs;           // per device (scene key devices[].drive)
  std::vector<double> initial_inserted_length;  // [m]
  std::vector<double> initial_rotation;         // [rad]
  std::vector<int> outer_of;  // effect 'coaxial': per device its outer device (-1); else empty
  std::vector<ScriptedCommand> script;
  double duration{1.0};               // [s] of the scripted procedure (SceneSpec::duration)
  std::vector<std::string> warnings;  // from loading: a usable but suspect vessel tree
};

/// Statistics of the last step (reset every step; sums over its sub-steps).
/// One step's statistics, each stage's as it measured them. The stages are
/// consecutive on one clock (StageTimer): free_motion's three,
/// vessel_motion_ms, contact.times' five (ContactTimes::stagesMs) and
/// other_ms add up to wall_ms (stagesMs()).
struct StepStats {
  double wall_ms{0.0};           // whole step [ms]
  FreeMotionTimes free_motion;   // [ms] all devices, every attempt
  double vessel_motion_ms{0.0};  // [ms] effects 'vessel_motion', 'vessel_deformation': the
                                 // motion snapshot, the wall's step
  ContactStats contact;          // times of every attempt, results of the accepted sub-steps
  double other_ms{0.0};  // [ms] the rest: script, drives, state copies, tips, forces, targets
  int subdivisions{0};   // sub-steps added by halving
  bool asleep{false};    // the scene slept through this step (SleepOptions): nothing was solved

  /// The stages' sum [ms]: wall_ms to the clock's rounding.
  double stagesMs() const {
    return free_motion.assembly_ms + free_motion.factorization_ms + free_motion.solve_ms +
           vessel_motion_ms + contact.times.stagesMs() + other_ms;
  }
};

enum class StepStatus { kOk, kSolverFailure, kContactsUnsolved };

/// Device states a (sub-)step at one depth of halving works in: the new
/// states and where the contact solver ended. Kept from step to step, so
/// that a step copies into storage of the right size instead of
/// allocating it.
struct SubStepStates {
  std::vector<DeviceState> next, moved;
};

struct SimData {
  double time{0.0};  // [s]
  long step{0};
  std::vector<DeviceState> devices;
  std::vector<DriveCommand> commands;
  std::vector<DeviceWorkspace> workspaces;
  std::vector<Contact> contacts;                          // of the last (sub-)step, with forces
  std::vector<std::vector<InteriorBall>> interior_balls;  // detection's, per device sample
  bool record_lcp{false};  // keep the last LCP in `lcp` (dumps, tests)
  LcpRecord lcp;
  size_t next_script_entry{0};
  StepStats stats;
  EffectCounters effect_calls;
  std::vector<VesselLocation> tips;     // per device: where its distal tip is (with vessels)
  std::vector<DriveWrench> drives;      // per device: what its drive applies (drive_wrench.h)
  std::vector<DriveStall> stalls;       // per device: what its drive cannot impose (limits reached)
  std::vector<double> stall_noticed;    // per device: when a stall was last told [s]
  std::vector<Vec3> tip_forces;         // per device: contact force on its last kTipLength [N]
  std::vector<TargetProgress> targets;  // per scene target
  int resting_steps{0};                 // consecutive steps in which nothing moved (SleepOptions)
  bool asleep{false};                   // steps only advance the clock until wake()
  std::string last_error;               // why the last failed step was rejected
  std::vector<std::string>
      notices;  // scripted commands refused, drives at a limit (runners print and clear them)
  // Storage and caches the steps reuse; what they hold changes a step's
  // answer by round-off at most (a copy of the data steps as the original).
  ContactWorkspace contact_workspace;  // pair candidates, the loops' rows
  std::deque<SubStepStates> substeps;  // per depth of halving
  // Effect 'vessel_deformation': the wall's shape now (null: at rest) and
  // the factor its steps solve with.
  std::shared_ptr<const WallShape> wall;
  VesselWall::StepFactor wall_factor;
};

/// Throws LoadError when the spec is beyond the limits its scene states
/// (checkSceneLimits: a changed time step or discretisation).
SceneModel buildSceneModel(const SceneSpec& spec);

/// Loads a scene by name or path (throws LoadError).
SceneModel loadScene(const std::string& name_or_path);

/// Fresh data at the scene's initial state.
SimData makeData(const SceneModel& model);

/// Index of a device by name, -1 when unknown.
int findDevice(const SceneModel& model, const std::string& name);

/// Detaches a device's detach_section (a coil from its pusher): the element
/// joining them is cut. Refused (with the reason; nothing changes) for an
/// unknown device, one without a detach_section, one already detached, and
/// while the junction has not wholly left the introducer (the
/// microcatheter). Afterwards the pusher is driven as before and the coil is
/// free.
std::string detachDevice(const SceneModel& model, SimData* data, const std::string& device);

/// Ends the scene's sleep (and its count of resting steps): the next step
/// is solved. setCommand (a changed command), the script and detachDevice
/// call it; so must a caller that changes the state or the model by hand.
void wake(SimData* data);

/// Sets device `device`'s drive command as a controller does at each tick
/// (the command already within the device's limits), waking the scene when
/// it changes: a sleeping scene (a drive stalled against a wall rests too)
/// follows a new command at once.
void applyCommand(SimData* data, int device, const DriveCommand& command);

/// Sets a device's drive command; returns why it was refused ("" if accepted).
std::string setCommand(const SceneModel& model, SimData* data, const std::string& device,
                       const DriveCommand& command);

/// Where a point [m] is among the scene's named vessels at the data's time
/// (moving vessels: the point is taken back to the vessels' rest position).
VesselLocation locateInVessels(const SceneModel& model, const SimData& data, const Vec3& p);

/// The distal length whose contact forces make a device's tip force [m].
constexpr double kTipLength = 5e-3;

/// Recomputes data->drives and data->tip_forces from the state and the
/// contacts, and data->stalls from the drives and the scene's drive limits
/// (step() does it after every step: the next step's drives do not move a
/// device in a direction whose resistance reached the limit). The
/// introducer valve's friction (DriveSpec) is added by step() alone, which
/// knows the drive's motion.
void measureForces(const SceneModel& model, SimData* data);

/// Recomputes data->tips and the targets' progress at data->time (step()
/// does it after every step; call it after changing the state by hand).
void locateTips(const SceneModel& model, SimData* data);

/// The largest contact force [N] on the vessel wall (not a device's lumen,
/// not another device) of the last step.
double maxWallForce(const SimData& data);

/// Advances the simulation by model.time_step. On failure the previous state
/// is kept and data->last_error says why; no NaN ever reaches the state.
StepStatus step(const SceneModel& model, SimData* data);

/// The scene for a step that failed with the scene's own options: the
/// status method with its default tolerance and pivot limit, at least 40
/// activation loops and 8 halvings, the effect 'subdivision' on.
SceneModel recoveryModel(const SceneModel& model);

/// The one recovery policy of every runner (evsim, the node, Python,
/// rollouts): step(), and when it fails, the same step again at once with
/// recoveryModel (*recovered set then, data->last_error saying why the
/// scene's options failed). kOk when either succeeded; otherwise the data
/// is at the last good step and data->last_error says why both failed.
StepStatus stepOrRecover(const SceneModel& model, SimData* data, bool* recovered);

}  // namespace evsim
