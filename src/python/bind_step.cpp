// step(), the drive commands, detachment and where the tips are.
#include <pybind11/stl.h>

#include <cmath>

#include "endovascular_sim/sim/targets.h"
#include "py_simulation.h"

namespace evsim::python {

namespace {

DriveCommand::Mode modeOf(const std::string& mode) {
  if (mode == "velocity") return DriveCommand::Mode::kVelocity;
  if (mode == "position") return DriveCommand::Mode::kPosition;
  throw py::value_error("mode '" + mode + "': use 'velocity' ([m/s], [rad/s]) or 'position' ([m], [rad])");
}

const VesselAtlas& atlasOf(const SceneModel& m) {
  if (!m.atlas) throw py::value_error("scene '" + m.name + "' has no vessels");
  return *m.atlas;
}

int vesselIndex(const SceneModel& m, const std::string& name) {
  const int v = atlasOf(m).find(name);
  if (v >= 0) return v;
  std::string near;
  for (const std::string& c : m.atlas->closestNames(name)) near += (near.empty() ? "" : ", ") + c;
  throw py::value_error("no vessel '" + name + "' in scene '" + m.name + "' (nearest: " + near + ")");
}

}  // namespace

void bindStep(py::module_& m) {
  static py::exception<std::runtime_error> step_error(m, "StepError", PyExc_RuntimeError);
  m.def(
      "step",
      [](const PyModel& model, PyData& data, long nstep, bool recover) {
        requireCompatible(model, data);
        if (nstep < 0) throw py::value_error("nstep must not be negative, got " + std::to_string(nstep));
        const SceneModel& sm = data.model();
        std::string failure;
        long recovered = 0;
        {
          py::gil_scoped_release release;
          for (long k = 0; k < nstep; ++k) {
            bool r = false;
            const StepStatus s = recover ? stepOrRecover(sm, &data.data, &r) : step(sm, &data.data);
            recovered += r;
            if (s != StepStatus::kOk) {
              failure = "step " + std::to_string(data.data.step + 1) + " at t = " +
                        std::to_string(data.data.time) + " s failed: " + data.data.last_error;
              break;
            }
          }
        }
        if (!failure.empty()) {
          PyErr_SetString(step_error.ptr(), failure.c_str());
          throw py::error_already_set();
        }
        return recovered;
      },
      py::arg("model"), py::arg("data"), py::arg("nstep") = 1, py::arg("recover") = true,
      "Advances `nstep` steps of model.time_step with the GIL released. A step the scene's "
      "options cannot solve is tried once more with the recovery options (recover=True, as "
      "evsim run does); a step that fails even so raises StepError, the data keeping the last "
      "good state. Returns how many steps needed the recovery options.");
  m.def(
      "set_command",
      [](const PyModel& model, PyData& data, py::handle device, double insertion, double rotation,
         const std::string& mode) {
        requireCompatible(model, data);
        const int d = deviceIndex(data.model(), device);
        const std::string why = setCommand(data.model(), &data.data, data.model().devices[d].name,
                                           DriveCommand{modeOf(mode), insertion, rotation});
        if (!why.empty()) throw py::value_error(why);
      },
      py::arg("model"), py::arg("data"), py::arg("device"), py::arg("insertion"),
      py::arg("rotation"), py::arg("mode") = "velocity",
      "A device's drive command: velocity mode insertion [m/s] and rotation [rad/s], or "
      "position mode inserted length [m] and angle [rad]. Refused (ValueError, nothing "
      "changes) when not finite or beyond the device's limits.");
  m.def(
      "command",
      [](const PyModel& model, const PyData& data, py::handle device) {
        requireCompatible(model, data);
        const DriveCommand& c = data.data.commands[deviceIndex(data.model(), device)];
        return py::make_tuple(c.insertion, c.rotation,
                              c.mode == DriveCommand::Mode::kPosition ? "position" : "velocity");
      },
      py::arg("model"), py::arg("data"), py::arg("device"),
      "A device's drive command: (insertion, rotation, mode)");
  m.def(
      "detach",
      [](const PyModel& model, PyData& data, py::handle device) {
        requireCompatible(model, data);
        const int d = deviceIndex(data.model(), device);
        const std::string why = detachDevice(data.model(), &data.data, data.model().devices[d].name);
        if (!why.empty()) throw py::value_error(why);
      },
      py::arg("model"), py::arg("data"), py::arg("device"),
      "Detaches a coil from its pusher (ValueError with the reason when refused)");
  m.def(
      "locate",
      [](const PyModel& model, const PyData& data, const std::array<double, 3>& point) {
        requireCompatible(model, data);
        atlasOf(data.model());
        const VesselLocation at = locateInVessels(data.model(), data.data, Vec3(point[0], point[1], point[2]));
        py::dict out;
        out["vessel"] = data.model().atlas->vessels()[at.vessel].name;
        out["depth"] = at.depth;
        out["radial"] = at.radial;
        out["in_lumen"] = at.inside;
        return out;
      },
      py::arg("model"), py::arg("data"), py::arg("point"),
      "Where a point [m] lies among the named vessels: vessel, depth [m], radial (distance "
      "from the centreline over the radius), in_lumen");
  m.def(
      "remaining_path",
      [](const PyModel& model, const PyData& data, py::handle device, const std::string& vessel,
         double depth) {
        requireCompatible(model, data);
        const SceneModel& sm = data.model();
        const VesselAtlas& atlas = atlasOf(sm);
        const int d = deviceIndex(sm, device);
        const int v = vesselIndex(sm, vessel);
        if (!(depth >= 0.0) || !std::isfinite(depth))
          throw py::value_error("depth must be a finite length >= 0 [m]");
        if (static_cast<size_t>(d) >= data.data.tips.size()) return std::nan("");
        const VesselLocation& at = data.data.tips[d];
        const std::vector<int> path = atlas.path(at.vessel, v);
        if (path.empty()) return std::numeric_limits<double>::infinity();
        return atlas.pathLength(path, at.depth, requiredDepth(atlas.vessels()[v], depth));
      },
      py::arg("model"), py::arg("data"), py::arg("device"), py::arg("vessel"),
      py::arg("depth") = 0.02,
      "Path length [m] along the centrelines from the device's tip to `depth` inside a vessel "
      "(the autopilot's measure of progress; inf when not connected)");
  m.def(
      "required_depth",
      [](const PyModel& model, const std::string& vessel, double depth) {
        const SceneModel& sm = model.get();
        return requiredDepth(atlasOf(sm).vessels()[vesselIndex(sm, vessel)], depth);
      },
      py::arg("model"), py::arg("vessel"), py::arg("depth") = 0.02,
      "How deep [m] a tip must be in a vessel to hold a target of that depth");
}

}  // namespace evsim::python
