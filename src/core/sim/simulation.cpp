// The simulation: an immutable SceneModel built once per scene, the SimData
// workspace it steps, and step() — the pipeline of the paper. Declared and
// documented in endovascular_sim/sim/simulation.h.
#include "endovascular_sim/sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>

#include "endovascular_sim/contact/coaxial.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/sim/drives.h"
#include "endovascular_sim/sim/initial_placement.h"

namespace evsim {
namespace {

bool sameCommand(const DriveCommand& a, const DriveCommand& b) {
  return a.mode == b.mode && a.insertion == b.insertion && a.rotation == b.rotation;
}

void applyScript(const SceneModel& model, SimData* data) {
  while (data->next_script_entry < model.script.size() &&
         model.script[data->next_script_entry].time <= data->time + 1e-12) {
    const ScriptedCommand& c = model.script[data->next_script_entry++];
    if (!c.detach) {
      if (!sameCommand(data->commands[c.device], c.command)) wake(data);
      data->commands[c.device] = c.command;
      continue;
    }
    const std::string why = detachDevice(model, data, model.devices[c.device].name);
    if (!why.empty())
      data->notices.push_back("script at t = " + std::to_string(c.time) +
                              " s: detach refused: " + why);
  }
}

/// Why the contacts of a (sub-)step were not solved, and the knob that helps.
std::string unsolvedContacts(const SceneModel& model, const ContactStats& cs) {
  const ContactOptions& o = model.contact;
  std::ostringstream why;
  if (cs.lcp_status == LcpStatus::kInfeasible || cs.lcp_status == LcpStatus::kUnsolved) {
    why << "the contact problem of " << cs.contacts << " contacts "
        << (cs.lcp_status == LcpStatus::kInfeasible ? "has no solution" : "was not solved")
        << " (LCP solver '" << lcpSolverName(o.lcp.solver) << "', natural residual "
        << cs.lcp_residual << " in activation loop " << cs.activation_loops
        << "): the contacts cannot all hold, as when a device is pushed into a lumen narrower "
           "than it or squeezed into a dead end; a drive limit (devices[].drive) lets it stall";
  } else if (cs.lcp_status != LcpStatus::kSolved) {
    why << "the LCP solver '" << lcpSolverName(o.lcp.solver) << "' "
        << (cs.lcp_status == LcpStatus::kIterationLimit ? "reached its iteration limit" : "failed")
        << " on " << cs.contacts << " contacts (residual " << cs.lcp_residual
        << " m) in activation loop " << cs.activation_loops << ": "
        << (o.lcp.solver == LcpSolver::kStatusMethod
                ? "raise contact.max_iterations (now " +
                      (o.lcp.max_iterations > 0 ? std::to_string(o.lcp.max_iterations)
                                                : std::string("automatic")) +
                      "), or look for a load far beyond the devices' own (gravity, a drive "
                      "force) that makes the contacts stiff"
                : std::string("use the status method (contact.solver: status), or raise "
                              "contact.max_iterations"));
  } else if (!std::isfinite(cs.max_penetration_m)) {
    // Beyond the field's support: no depth to report, only where it is.
    const Vec3 at = cs.deepest_point * 1e3;
    why << "contacts not solved in " << cs.activation_loops << " activation loops: a point of "
        << "device '"
        << (cs.deepest_device >= 0 ? model.devices[cs.deepest_device].name : std::string("?"))
        << "' lies outside the vessel tree, at (" << at.x() << ", " << at.y() << ", " << at.z()
        << ") mm, with " << cs.contacts
        << " contacts: it left the lumen between two steps (a device placed or driven "
           "through the wall)";
  } else {
    why << "contacts not solved in " << cs.activation_loops << " activation loops: the deepest "
        << "point is " << cs.max_penetration_m * 1e6 << " um beyond the wall (tolerance "
        << o.penetration_tolerance * 1e6 << " um) with " << cs.contacts
        << " contacts: raise contact.max_activation_loops (now " << o.max_activation_loops << ")"
        << (model.effects.subdivision
                ? ", or contact.max_subdivisions (now " + std::to_string(o.max_subdivisions) + ")"
                : std::string(", or add the effect 'subdivision' (halved steps)"));
  }
  return why.str();
}

/// The states of a (sub-)step at one depth of halving (SimData::substeps),
/// added as deeper halvings first need them (a deque: adding does not move
/// the others).
SubStepStates& subStepStates(SimData* data, int depth) {
  while (static_cast<int>(data->substeps.size()) <= depth) data->substeps.emplace_back();
  return data->substeps[depth];
}

/// One (sub-)step of length dt from data->devices; on success the new
/// states in *next. *moved: storage for where the contact solver ends.
StepStatus subStep(const SceneModel& model, SimData* data, double dt,
                   std::vector<DeviceState>* next, std::vector<DeviceState>* moved,
                   StageTimer* clock) {
  *next = data->devices;
  for (size_t i = 0; i < model.devices.size(); ++i) {
    advanceDrive(data->commands[i], model.devices[i], dt, &(*next)[i],
                 i < data->stalls.size() ? data->stalls[i] : DriveStall{});
    if (model.effects.gravity) ++data->effect_calls.gravity;
    if (model.effects.blood_drag) ++data->effect_calls.blood_drag;
    // The sheath holds a device leaving it; a device inside another, that
    // device's lumen does.
    const bool outermost = i >= model.outer_of.size() || model.outer_of[i] < 0;
    if (!computeFreeMotion(model.devices[i], model.introducers[i], model.gravity, dt, (*next)[i],
                           &data->workspaces[i], &data->stats.free_motion, clock, outermost)) {
      data->last_error = "device '" + model.devices[i].name +
                         "': the system matrix is not positive definite or the solve diverged";
      return StepStatus::kSolverFailure;
    }
  }
  std::vector<Contact> previous;  // the last (sub-)step's contacts: persisting planes
  previous.swap(data->contacts);
  // x_t (+) dq, where the contact solver ended (it takes the storage).
  bool already_moved = false;
  if (model.surface || model.effects.device_contact || model.effects.coaxial) {
    ContactProblem pb;
    pb.effects = model.effects;
    pb.previous = &previous;
    pb.devices = &model.devices;
    pb.start = next;
    pb.workspaces = &data->workspaces;
    pb.kept = &data->contact_workspace;
    pb.samples = &model.samples;
    pb.surface = model.surface.get();
    pb.interior = &data->interior_balls;
    pb.end = moved;
    if (model.effects.coaxial) pb.outer_of = &model.outer_of;
    if (model.effects.vessel_motion) {
      clock->begin();
      pb.motion = model.surface->motionAt(data->time + dt);
      clock->end(&data->stats.vessel_motion_ms);
      ++data->effect_calls.vessel_motion;
    }
    if (model.effects.vessel_deformation) pb.motion.wall = data->wall;  // as the last step left it
    if (data->record_lcp) {
      data->lcp = LcpRecord{};
      pb.record = &data->lcp;
    }
    ContactStats cs;
    const bool solved = resolveContacts(pb, model.contact, &data->contacts, &cs, clock);
    data->stats.contact.times += cs.times;
    data->effect_calls.device_contact += cs.pair_passes;
    data->effect_calls.friction += cs.friction_solves;
    data->effect_calls.coaxial += cs.lumen_passes;
    if (!solved) {
      data->contacts.swap(previous);  // a subdivided step starts from them again
      data->last_error = unsolvedContacts(model, cs);
      return StepStatus::kContactsUnsolved;
    }
    data->stats.contact.addSubStep(cs);
    already_moved = moved->size() == model.devices.size();
  }
  if (already_moved) next->swap(*moved);  // the same numbers commitMotion would compute
  for (size_t i = 0; i < model.devices.size(); ++i) {
    if (already_moved)
      setStepVelocities(data->workspaces[i].dq, dt, &(*next)[i]);
    else
      commitMotion(data->workspaces[i].dq, dt, &(*next)[i]);
    for (const Vec3& x : (*next)[i].position)
      if (!x.allFinite()) {
        data->last_error = "device '" + model.devices[i].name + "': a position is not finite";
        return StepStatus::kSolverFailure;
      }
  }
  return StepStatus::kOk;
}

/// Effect 'vessel_deformation': one step of dt [s] of the wall under the
/// reactions of the contacts just solved (-lambda n at each wall contact,
/// shared by the two centreline points of the segment nearest to it); the
/// next step's contacts are solved against the shape it takes. A point
/// moves, and a radius widens, by at most the scene's wall reach.
void giveWay(const SceneModel& model, SimData* data, double dt, StageTimer* clock) {
  clock->begin();
  ++data->effect_calls.vessel_deformation;
  const VesselWall& wall = *model.wall;
  const int n = wall.numNodes();
  MotionSnapshot now;
  if (model.effects.vessel_motion) now = model.vessels->motionAt(data->time);
  now.wall = data->wall;
  std::vector<Vec3> loads(n, Vec3::Zero());
  std::vector<double> pressing(n, 0.0);  // [N] outward, per centreline point
  for (const Contact& c : data->contacts) {
    if (c.other_device >= 0 || c.lumen || !(c.force > 0.0)) continue;
    int a = 0, b = 0;
    double t = 0.0;
    if (!model.vessels->nearestSegment(c.point, now, &a, &b, &t)) continue;
    loads[a] -= (1.0 - t) * c.force * c.normal;
    loads[b] -= t * c.force * c.normal;
    pressing[a] += (1.0 - t) * c.force;
    pressing[b] += t * c.force;
  }
  auto shape = std::make_shared<WallShape>();
  shape->version = newWallShapeVersion();
  shape->displacement = data->wall ? data->wall->displacement : std::vector<Vec3>(n, Vec3::Zero());
  wall.step(loads, dt, &data->wall_factor, &shape->displacement);
  shape->radius_change.resize(n);
  const double reach = model.wall_reach;
  for (int i = 0; i < n; ++i) {
    Vec3& u = shape->displacement[i];
    if (u.norm() > reach) u *= reach / u.norm();
    shape->radius_change[i] =
        std::min(wall.radiusChange(i, pressing[i] / wall.nodeLength(i)), reach);
  }
  data->wall = std::move(shape);
  clock->end(&data->stats.vessel_motion_ms);
}

/// Advances by dt; a step whose contacts are not solved is redone as two
/// halves, recursively up to the subdivision limit. On failure data->devices
/// is unchanged.
StepStatus advance(const SceneModel& model, SimData* data, double dt, int depth,
                   StageTimer* clock) {
  SubStepStates& buffers = subStepStates(data, depth);
  std::vector<DeviceState>& next = buffers.next;
  const StepStatus status = subStep(model, data, dt, &next, &buffers.moved, clock);
  if (status == StepStatus::kOk) {
    // Copied, not swapped: the data's node arrays keep their storage (the
    // Python front's arrays view them).
    for (size_t i = 0; i < next.size(); ++i) copyState(next[i], &data->devices[i]);
    data->time += dt;
    if (model.effects.vessel_deformation) giveWay(model, data, dt, clock);
    return status;
  }
  if (status != StepStatus::kContactsUnsolved || !model.effects.subdivision ||
      depth >= model.contact.max_subdivisions)
    return status;
  ++data->effect_calls.subdivision;
  const std::vector<DeviceState> saved = data->devices;
  const double saved_time = data->time;
  const std::shared_ptr<const WallShape> saved_wall = data->wall;
  data->stats.subdivisions += 1;
  for (int half = 0; half < 2; ++half) {
    const StepStatus s = advance(model, data, 0.5 * dt, depth + 1, clock);
    if (s != StepStatus::kOk) {
      for (size_t i = 0; i < saved.size(); ++i) copyState(saved[i], &data->devices[i]);
      data->time = saved_time;
      data->wall = saved_wall;
      return s;
    }
  }
  return StepStatus::kOk;
}

/// Counts the step just taken as resting when no drive moved (inserted
/// length and angle as `before`) and no node moved more than
/// SleepOptions::displacement; after SleepOptions::steps such steps the
/// scene sleeps, its velocities zeroed.
void noteRest(const SceneModel& model, const std::vector<DriveReading>& before, SimData* data) {
  const SleepOptions& o = model.sleep;
  if (!o.enabled || model.effects.vessel_motion) return;
  const double dt = model.time_step;
  bool rest = data->stats.subdivisions == 0;
  for (size_t i = 0; i < model.devices.size() && rest; ++i) {
    const DeviceState& x = data->devices[i];
    rest = x.inserted_length == before[i].inserted && x.rotation_angle == before[i].angle;
    double arm = 0.0;  // a node's turn moves its element's far end by angle * length
    for (const auto& e : model.devices[i].elements) arm = std::max(arm, e.length);
    for (size_t n = 0; n < x.position.size() && rest; ++n)
      rest = x.velocity[n].norm() * dt <= o.displacement &&
             x.angular_velocity[n].norm() * dt * arm <= o.displacement;
  }
  data->resting_steps = rest ? data->resting_steps + 1 : 0;
  if (data->resting_steps < o.steps) return;
  data->asleep = true;
  for (DeviceState& x : data->devices) {
    for (Vec3& v : x.velocity) v.setZero();
    for (Vec3& w : x.angular_velocity) w.setZero();
  }
}

/// The statistics of a step slept through: the kept contacts.
void sleepingStep(SimData* data) {
  data->stats.asleep = true;
  data->stats.contact.contacts = static_cast<int>(data->contacts.size());
  for (const Contact& c : data->contacts) data->stats.contact.active_contacts += c.force > 0.0;
}

/// The targets' dwell at data->time, from the tips where they are.
void trackTargets(const SceneModel& model, SimData* data) {
  if (!model.atlas || model.targets.empty()) return;
  for (std::string& notice : updateTargets(model.targets, data->tips, model.devices, data->devices,
                                           *model.atlas, data->time, &data->targets))
    data->notices.push_back(std::move(notice));
}

}  // namespace

void locateTips(const SceneModel& model, SimData* data) {
  if (!model.atlas) return;
  data->tips.resize(data->devices.size());
  for (size_t i = 0; i < data->devices.size(); ++i)
    data->tips[i] = locateInVessels(model, *data, data->devices[i].position.back());
  trackTargets(model, data);
}

VesselLocation locateInVessels(const SceneModel& model, const SimData& data, const Vec3& p) {
  if (!model.atlas) return {};
  if (!model.effects.vessel_motion || !model.vessels || !model.vessels->moves())
    return model.atlas->locate(p);
  const MotionSnapshot motion = model.vessels->motionAt(data.time);
  return model.atlas->locate(p - model.vessels->displacement(p, motion));
}

SimData makeData(const SceneModel& model) {
  SimData d;
  const size_t n = model.devices.size();
  placeDevices(model, &d.devices);  // a length that does not fit was refused at load
  d.commands.assign(n, DriveCommand{});
  d.notices = model.warnings;  // runners print them with the first step's notices
  d.workspaces = std::vector<DeviceWorkspace>(n);
  locateTips(model, &d);
  measureForces(model, &d);
  return d;
}

int findDevice(const SceneModel& model, const std::string& name) {
  for (size_t i = 0; i < model.devices.size(); ++i)
    if (model.devices[i].name == name) return static_cast<int>(i);
  return -1;
}

std::string detachDevice(const SceneModel& model, SimData* data, const std::string& device) {
  const int i = findDevice(model, device);
  if (i < 0) return "unknown device '" + device + "'";
  const DeviceModel& m = model.devices[i];
  DeviceState& state = data->devices[i];
  if (m.detach_element < 0) return "device '" + device + "' has no detach_section";
  if (state.cut_element >= 0) return "device '" + device + "' is already detached";
  // The junction element must be wholly past the access point and, inside
  // an outer device (effect 'coaxial'), past that device's tip.
  double needed = m.length - m.node_s[m.detach_element];
  const int outer = model.outer_of.empty() ? -1 : model.outer_of[i];
  if (outer >= 0) needed += data->devices[outer].inserted_length;
  if (state.inserted_length < needed) {
    std::ostringstream why;
    why << "the junction of device '" << device << "' is still in "
        << (outer >= 0 ? "the " + model.devices[outer].name : std::string("the introducer"))
        << ": inserted " << state.inserted_length * 1e3 << " mm, detaching needs at least "
        << needed * 1e3 << " mm";
    return why.str();
  }
  state.cut_element = m.detach_element;
  wake(data);
  return "";
}

SceneModel recoveryModel(const SceneModel& model) {
  SceneModel m = model;
  m.contact.lcp = LcpOptions{};  // the status method, automatic pivot limit, default tolerance
  m.contact.max_activation_loops = std::max(m.contact.max_activation_loops, 40);
  m.contact.max_subdivisions = std::max(m.contact.max_subdivisions, 8);
  m.effects.subdivision = true;
  return m;
}

StepStatus stepOrRecover(const SceneModel& model, SimData* data, bool* recovered) {
  *recovered = false;
  const StepStatus status = step(model, data);
  if (status == StepStatus::kOk) return status;
  const std::string why = data->last_error;
  const StepStatus retry = step(recoveryModel(model), data);
  *recovered = retry == StepStatus::kOk;
  data->last_error = *recovered ? why : why + "; with the recovery options: " + data->last_error;
  return retry;
}

void wake(SimData* data) {
  data->asleep = false;
  data->resting_steps = 0;
}

std::string setCommand(const SceneModel& model, SimData* data, const std::string& device,
                       const DriveCommand& command) {
  const int i = findDevice(model, device);
  if (i < 0) return "unknown device '" + device + "'";
  std::string why = validateDriveCommand(command, model.devices[i]);
  if (!why.empty()) return why;
  applyCommand(data, i, command);
  return "";
}

void applyCommand(SimData* data, int device, const DriveCommand& command) {
  if (!sameCommand(data->commands[device], command)) wake(data);
  data->commands[device] = command;
}

double maxWallForce(const SimData& data) {
  double f = 0.0;
  for (const Contact& c : data.contacts)
    if (c.other_device < 0 && !c.lumen) f = std::max(f, c.force);
  return f;
}

StepStatus step(const SceneModel& model, SimData* data) {
  data->stats = StepStats{};
  StageTimer clock(&data->stats.other_ms);
  applyScript(model, data);
  const double t_end = data->time + model.time_step;
  if (data->asleep) {
    data->time = t_end;
    ++data->step;
    sleepingStep(data);
    trackTargets(model, data);  // the tips rest where they are: a dwell goes on
    clock.begin();
    data->stats.wall_ms = clock.elapsedMs();
    return StepStatus::kOk;
  }
  const std::vector<DriveReading> before = readDrives(*data);
  const StepStatus status = advance(model, data, model.time_step, 0, &clock);
  if (status == StepStatus::kOk) {
    data->time = t_end;  // no drift from summed halves
    ++data->step;
    noteDriveLimits(model, before, data);
    locateTips(model, data);
    measureForcesSince(model, data, &before);
    noteRest(model, before, data);
  } else {
    data->resting_steps = 0;
  }
  clock.begin();
  data->stats.wall_ms = clock.elapsedMs();
  return status;
}

}  // namespace evsim
