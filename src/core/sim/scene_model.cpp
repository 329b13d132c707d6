// The scene model built from a scene file's spec (sim/simulation.h):
// effects, the vessels' field and atlas, the devices and their samples,
// checks of the access points and targets against the vessels.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/patient_frame.h"
#include "endovascular_sim/mechanics/blood_drag.h"
#include "endovascular_sim/sim/initial_placement.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

/// The radii [m] of every sample point: the widths detection evaluates the
/// vessel field for.
std::vector<double> sampleRadii(const std::vector<std::vector<SamplePoint>>& samples) {
  std::vector<double> radii;
  for (const auto& device : samples)
    for (const SamplePoint& s : device)
      if (std::find(radii.begin(), radii.end(), s.radius) == radii.end()) radii.push_back(s.radius);
  return radii;
}

/// Every device's access point lies in a lumen wide enough for it: else the
/// first step fails with the device beyond the wall; refused at load with
/// the distance to the wall.
void checkAccessPoints(const SceneSpec& spec, const VesselField* vessels) {
  if (!vessels) return;
  for (size_t i = 0; i < spec.devices.size(); ++i) {
    const DevicePlacementSpec& d = spec.devices[i];
    if (d.outer >= 0) continue;  // enters through its outer device
    double radius = 0.0;
    for (const auto& sec : d.device.sections) radius = std::max(radius, sec.section.outer_radius);
    const FieldSample g = vessels->evaluate(d.introducer.access_point, radius);
    if (g.value >= 0.0) continue;
    std::ostringstream why;
    const double slope = g.gradient.norm();
    if (slope > 0.0)
      why << "lies " << -g.value / slope * 1e3 << " mm beyond the wall of the vessels for a device "
          << "of radius " << radius * 1e3 << " mm: move it into a lumen";
    else
      why << "lies outside every vessel: move it into a lumen";
    throw LoadError(spec.file, d.access_point_line,
                    "devices[" + std::to_string(i) + "].access_point", why.str());
  }
}

/// Every device's inserted length fits inside the lumen as it is placed
/// (sim/initial_placement.h); refused with the length that fits.
void checkPlacement(const SceneSpec& spec, const SceneModel& m) {
  std::vector<DeviceState> placed;
  int bad = -1;
  const std::string why = placeDevices(m, &placed, &bad);
  if (why.empty()) return;
  throw LoadError(spec.file, spec.devices[bad].inserted_length_line,
                  "devices[" + std::to_string(bad) + "].inserted_length", why);
}

/// Devices that overlap as they are placed (effect 'device_contact': two
/// devices whose access points put them through each other, a coil whose
/// rest shape passes through itself) are refused with the two elements and
/// the depth: the first step would have to push them apart by that much,
/// and a pair deeper than its radii has no side to be pushed to.
void checkDeviceOverlaps(const SceneSpec& spec, const SceneModel& m) {
  constexpr double kTolerance = 1e-5;  // [m]
  SimData data = makeData(m);
  for (size_t i = 0; i < m.devices.size(); ++i)
    data.workspaces[i].first_free_node =
        lastHeldNode(m.devices[i], data.devices[i].inserted_length) + 1;
  ContactProblem pb;
  pb.effects = m.effects;
  pb.devices = &m.devices;
  pb.start = &data.devices;
  pb.workspaces = &data.workspaces;
  pb.samples = &m.samples;
  pb.outer_of = &m.outer_of;
  const std::vector<DeviceOverlap> overlaps =
      deviceOverlaps(pb, kTolerance, m.contact.element_pairs);
  if (overlaps.empty()) return;
  const DeviceOverlap& o = overlaps.front();
  std::ostringstream why;
  why << "as placed, element " << o.element_a << " of '" << m.devices[o.device_a].name
      << "' and element " << o.element_b << " of '" << m.devices[o.device_b].name << "' overlap by "
      << o.depth * 1e3 << " mm";
  if (overlaps.size() > 1) why << " (and " << overlaps.size() - 1 << " more pairs of elements)";
  why << ": move an access point, or change the inserted length";
  throw LoadError(spec.file, spec.devices[o.device_a].access_point_line,
                  "devices[" + std::to_string(o.device_a) + "]", why.str());
}

/// A device whose introducer points across its vessel (more than 60 degrees
/// off the nearest centreline segment, and the wall ahead within 1.5 lumen
/// radii) meets the wall at once: warned. (A coil aimed into an aneurysm's
/// dome from its neck has millimetres ahead: not warned.)
void warnAcrossTheVessel(const SceneSpec& spec, const Centerline& c, const VesselField& field,
                         std::vector<std::string>* warnings) {
  for (size_t i = 0; i < spec.devices.size(); ++i) {
    const DevicePlacementSpec& d = spec.devices[i];
    if (d.outer >= 0) continue;  // enters through its outer device
    const Vec3& p = d.introducer.access_point;
    double best = std::numeric_limits<double>::infinity(), radius = 0.0;
    Vec3 axis = Vec3::Zero();
    for (int k = 0; k < c.numPoints(); ++k) {
      const int j = c.parent[k];
      if (j < 0) continue;
      const Vec3 ab = c.position[k] - c.position[j];
      if (ab.squaredNorm() <= 0.0) continue;
      const double t = std::clamp((p - c.position[j]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double dist = (p - (c.position[j] + t * ab)).norm();
      if (dist < best)
        best = dist, axis = ab.normalized(), radius = (1 - t) * c.radius[j] + t * c.radius[k];
    }
    if (axis.isZero()) continue;
    const Vec3 dir = d.introducer.frame.col(0);
    const double angle = std::acos(std::min(1.0, std::abs(dir.dot(axis)))) * 180.0 / M_PI;
    if (angle <= 60.0) continue;
    const double device_radius = d.device.sections.front().section.outer_radius;
    if (!firstRoot(field, p, p + 1.5 * radius * dir, device_radius).hit) continue;
    std::ostringstream w;
    w << spec.file << ": devices[" << i << "] (" << d.device.name << ") enters at "
      << std::lround(angle) << " degrees to the axis of its vessel and meets the wall at once: "
      << "point insertion_direction along the vessel";
    warnings->push_back(w.str());
  }
}

/// The scene's targets against its vessels and devices: an unknown vessel,
/// one narrower than the device that must reach it, or one not connected to
/// the device's access point is refused with what exists.
/// An aneurysm target: its dome, and its device, which must have a section
/// that detaches (a coil).
template <typename Fail>
Target aneurysmTarget(const SceneSpec& spec, const TargetSpec& t, const Fail& fail) {
  Target target{t, -1, -1};
  const AneurysmSpec& a = spec.vessels.aneurysms.at(t.aneurysm);  // (index checked at load)
  target.center = a.center;
  target.radius = a.radius;
  for (size_t i = 0; i < spec.devices.size(); ++i)
    if (spec.devices[i].device.name == t.device) target.device = static_cast<int>(i);
  if (target.device < 0) fail("no device '" + t.device + "' in the scene");
  const DeviceSpec& coil = spec.devices[target.device].device;
  if (coil.detach_section.empty())
    fail("device '" + t.device +
         "' has no section that detaches (detach_section): an aneurysm target is a detached "
         "coil inside the dome");
  // Packing density: the coil's volume (its wire as a cylinder of its outer
  // radius, from the detaching section on) over the dome's. Coiled aneurysms
  // reach 20-35 %, rarely 40 % (Sluzewski et al., Radiology 2004;
  // 231:653-658); beyond half the dome no coil fits.
  constexpr double kMostPacked = 0.5;
  double volume = 0.0;
  bool detached = false;
  for (const DeviceSectionSpec& s : coil.sections) {
    detached = detached || s.name == coil.detach_section;
    if (detached) volume += M_PI * s.section.outer_radius * s.section.outer_radius * s.length;
  }
  const double dome = 4.0 / 3.0 * M_PI * std::pow(a.radius, 3);
  if (volume > kMostPacked * dome) {
    std::ostringstream why;
    why << "the coil of device '" << t.device << "' (" << volume * 1e9 << " mm^3) would fill "
        << std::lround(100.0 * volume / dome) << " % of aneurysm " << t.aneurysm << "'s dome ("
        << dome * 1e9 << " mm^3, radius " << a.radius * 1e3 << " mm): coils fill 20-35 % of "
        << "an aneurysm, and no coil fits in more than half of it; take a shorter coil";
    fail(why.str());
  }
  return target;
}

std::vector<Target> resolveTargets(const SceneSpec& spec, const VesselAtlas* atlas) {
  std::vector<Target> out;
  for (size_t k = 0; k < spec.targets.size(); ++k) {
    const TargetSpec& t = spec.targets[k];
    const std::string field = "targets[" + std::to_string(k) + "]";
    auto fail = [&](const std::string& why) { throw LoadError(spec.file, t.line, field, why); };
    if (!atlas) fail("a target needs vessels");
    if (t.aneurysm >= 0) {
      out.push_back(aneurysmTarget(spec, t, fail));
      continue;
    }
    Target target{t, atlas->find(t.vessel), -1};
    if (target.vessel < 0) {
      std::string near;
      for (const std::string& n : atlas->closestNames(t.vessel))
        near += (near.empty() ? "" : ", ") + n;
      fail("no vessel '" + t.vessel + "' in the scene (" + std::to_string(atlas->vessels().size()) +
           " named vessels; nearest: " + near + ")");
    }
    for (size_t i = 0; i < spec.devices.size(); ++i)
      if (spec.devices[i].device.name == t.device) target.device = static_cast<int>(i);
    // Every device that may reach it: it must fit and start connected to it.
    for (size_t i = 0; i < spec.devices.size(); ++i) {
      if (target.device >= 0 && target.device != static_cast<int>(i)) continue;
      const DevicePlacementSpec& d = spec.devices[i];
      const double tip_radius = d.device.sections.back().section.outer_radius;
      const NamedVessel& v = atlas->vessels()[target.vessel];
      if (v.radius <= tip_radius) {
        std::ostringstream why;
        why << "vessel '" << t.vessel << "' narrows to " << v.radius * 1e3
            << " mm radius, the tip of device '" << d.device.name << "' is " << tip_radius * 1e3
            << " mm: the lumen is closed to it";
        fail(why.str());
      }
      const DevicePlacementSpec& entry = d.outer >= 0 ? spec.devices[d.outer] : d;
      const int start = atlas->locate(entry.introducer.access_point).vessel;
      if (atlas->path(start, target.vessel).empty())
        fail("vessel '" + t.vessel + "' is not connected to vessel '" +
             atlas->vessels()[start].name + "', where device '" + d.device.name + "' enters");
    }
    out.push_back(target);
  }
  return out;
}

/// The vessels' anatomical frame: the scene's `vessels.frame`, else the
/// file's declaration ("": neither); refused when the two disagree.
std::string anatomicalFrame(const SceneSpec& spec, const Centerline& centerline) {
  const std::string& declared = spec.vessels.frame;
  if (!declared.empty() && !centerline.frame.empty() && declared != centerline.frame)
    throw LoadError(spec.file, spec.vessels.frame_line, "vessels.frame",
                    "'" + declared + "' contradicts the frame '" + centerline.frame + "' that " +
                        spec.vessels.centerline_file + " declares");
  return declared.empty() ? centerline.frame : declared;
}

/// Gravity [m/s^2] of a scene with vessels: `supine` / `prone` toward the
/// frame's posterior / anterior (unset: supine when the frame is known); a
/// vector as given, with a warning when the frame is known and the vector
/// leans more than 30 degrees off the posterior-anterior axis.
Vec3 sceneGravity(const SceneSpec& spec, const std::string& frame,
                  std::vector<std::string>* warnings) {
  constexpr double kStandardGravity = 9.81;  // [m/s^2]
  // Unset: a patient on the table lies supine, when the frame says where.
  const std::string posture = spec.posture.empty() && spec.gravity_line == 0 && !frame.empty()
                                  ? std::string("supine")
                                  : spec.posture;
  if (!posture.empty()) {
    if (frame.empty())
      throw LoadError(spec.file, spec.gravity_line, "gravity",
                      "'" + posture +
                          "' needs the vessels' anatomical frame: " + spec.vessels.centerline_file +
                          " declares none; give vessels.frame (the orientation code of its "
                          "axes, e.g. LPS as DICOM and ITK write, RAS as 3D Slicer does)");
    const double sign = posture == "supine" ? 1.0 : -1.0;
    return sign * kStandardGravity * posteriorDirection(frame);
  }
  const Vec3 posterior = frame.empty() ? Vec3::Zero() : posteriorDirection(frame);
  const double g = spec.gravity.norm();
  if (!frame.empty() && g > 0.0 && std::abs(spec.gravity.dot(posterior)) < std::cos(M_PI / 6) * g) {
    std::ostringstream w;
    w << spec.file << ":" << spec.gravity_line << ": gravity [" << spec.gravity.transpose()
      << "] m/s^2 is not along the patient's posterior [" << posterior.transpose()
      << "] in the vessels' frame " << frame
      << ": a patient on the table, supine or prone, has it there (gravity: supine)";
    warnings->push_back(w.str());
  }
  return spec.gravity;
}

}  // namespace

namespace {

/// Per vessel of the centreline (vessel_names' order), its wall: the
/// scene's `vessels.wall`, or its own entry in `vessels.wall.vessels`
/// (a name no vessel has is refused).
std::vector<WallProperties> wallProperties(const SceneSpec& spec, const Centerline& c) {
  const WallSpec& w = spec.vessels.wall;
  std::vector<WallProperties> out(c.vessel_names.size(), w.all);
  for (size_t i = 0; i < w.vessels.size(); ++i) {
    const auto at = std::find(c.vessel_names.begin(), c.vessel_names.end(), w.vessels[i].name);
    if (at == c.vessel_names.end()) {
      std::string names;
      for (const std::string& n : c.vessel_names) names += (names.empty() ? "" : ", ") + n;
      throw LoadError(spec.file, w.vessels[i].line,
                      "vessels.wall.vessels[" + std::to_string(i) + "].name",
                      "no vessel '" + w.vessels[i].name + "' (the vessels: " + names + ")");
    }
    out[at - c.vessel_names.begin()] = w.vessels[i].properties;
  }
  return out;
}

/// The centreline points an introducer sheath holds at rest: those within
/// kSheathHold of a device's access point, or within their own radius.
std::vector<int> sheathedPoints(const SceneSpec& spec, const Centerline& c) {
  constexpr double kSheathHold = 5e-3;  // [m]
  std::vector<int> held;
  for (int i = 0; i < c.numPoints(); ++i)
    for (const DevicePlacementSpec& d : spec.devices)
      if ((c.position[i] - d.introducer.access_point).norm() <=
          std::max(kSheathHold, c.radius[i])) {
        held.push_back(i);
        break;
      }
  return held;
}

}  // namespace

SceneModel buildSceneModel(const SceneSpec& file_spec) {
  checkSceneLimits(file_spec);
  SceneSpec spec = file_spec;  // devices at the inlet placed below
  SceneModel m;
  m.name = spec.name;
  m.file = spec.file;
  m.time_step = spec.time_step;
  for (const auto& e : spec.effects)
    if (e == "gravity")
      m.effects.gravity = true;
    else if (e == "vessel_motion")
      m.effects.vessel_motion = true;
    else if (e == "device_contact")
      m.effects.device_contact = true;
    else if (e == "subdivision")
      m.effects.subdivision = true;
    else if (e == "friction")
      m.effects.friction = true;
    else if (e == "coaxial")
      m.effects.coaxial = true;
    else if (e == "blood_drag")
      m.effects.blood_drag = true;
    else if (e == "vessel_deformation")
      m.effects.vessel_deformation = true;
  std::shared_ptr<VesselField> field;  // tabulated once the devices' radii are known
  if (!spec.vessels.present && !spec.posture.empty())
    throw LoadError(spec.file, spec.gravity_line, "gravity",
                    "'" + spec.posture + "' needs vessels: their frame says where posterior is; " +
                        "free space takes a vector [x, y, z] m/s^2");
  if (m.effects.gravity) m.gravity = spec.gravity;
  if (spec.vessels.present) {
    const Centerline centerline = buildCenterline(spec.vessels, &m.warnings, spec.file);
    m.frame = anatomicalFrame(spec, centerline);
    if (m.effects.gravity) m.gravity = sceneGravity(spec, m.frame, &m.warnings);
    for (DevicePlacementSpec& d : spec.devices)
      if (d.at_inlet) d.introducer = inletIntroducer(centerline);
    // A device inside another enters through that one's introducer, known
    // only now for an outer device at the inlet.
    for (DevicePlacementSpec& d : spec.devices)
      if (d.outer >= 0) d.introducer = spec.devices[d.outer].introducer;
    VesselFieldOptions field_options = spec.vessels.field;
    if (m.effects.vessel_deformation) {
      m.wall = std::make_shared<const VesselWall>(centerline, wallProperties(spec, centerline),
                                                  sheathedPoints(spec, centerline));
      m.wall_reach = field_options.wall_reach = spec.vessels.wall.reach;
    }
    field = std::make_shared<VesselField>(
        centerline, spec.vessels.aneurysms,
        m.effects.vessel_motion ? spec.vessels.motion : std::vector<MotionRegion>{}, field_options);
    m.vessels = field;
    warnAcrossTheVessel(spec, centerline, *m.vessels, &m.warnings);
    m.surface = m.vessels;
    m.atlas = std::make_shared<const VesselAtlas>(centerline);
    m.centerline = std::make_shared<const Centerline>(centerline);
    m.aneurysms = spec.vessels.aneurysms;
  }
  m.xray = spec.xray;
  checkAccessPoints(spec, m.vessels.get());
  m.targets = resolveTargets(spec, m.atlas.get());
  m.contact = spec.contact;
  m.sleep = spec.sleep;
  if (m.effects.vessel_motion || m.effects.vessel_deformation) m.sleep.enabled = false;
  if (m.effects.vessel_deformation && !m.wall)
    throw LoadError(spec.file, 0, "effects",
                    "'vessel_deformation' needs vessels: it is their wall that gives way");
  for (const auto& d : spec.devices) {
    m.devices.push_back(buildDeviceModel(d.device));
    if (m.effects.blood_drag)
      setBloodDrag(Blood{spec.blood_viscosity, spec.blood_density}, &m.devices.back());
    m.introducers.push_back(d.introducer);
    m.drive_specs.push_back(d.drive);
    m.initial_inserted_length.push_back(d.inserted_length);
    m.initial_rotation.push_back(d.rotation);
    m.samples.push_back(sampleDevice(m.devices.back(), m.contact.contact_spacing));
    if (m.effects.coaxial) m.outer_of.push_back(d.outer);
  }
  if (field) field->tabulateHessianBounds(sampleRadii(m.samples));
  m.script = spec.script;
  m.duration = spec.duration;
  checkPlacement(spec, m);
  if (m.effects.device_contact) checkDeviceOverlaps(spec, m);
  return m;
}

SceneModel loadScene(const std::string& name_or_path) {
  return buildSceneModel(loadSceneFile(resolveScenePath(name_or_path)));
}

}  // namespace evsim
