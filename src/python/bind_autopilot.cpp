// The autopilot: steered tick by tick from Python, or run headless.
#include <pybind11/stl.h>

#include "endovascular_sim/sim/autopilot.h"
#include "py_simulation.h"

namespace evsim::python {

namespace {

/// An autopilot and the model it steers in.
struct PyAutopilot {
  std::shared_ptr<const PyModel> owner;
  Autopilot pilot;
};

py::dict reportOf(const AutopilotReport& r) {
  py::dict d;
  d["reached"] = r.reached;
  d["reason"] = r.reason;
  d["time"] = r.time;
  d["retries"] = r.retries;
  d["peak_wall_force"] = r.peak_wall_force;
  d["failed_steps"] = r.failed_steps;
  d["remaining_path"] = r.remaining_path;
  return d;
}

AutopilotOptions optionsOf(double timeout) {
  if (!(timeout > 0.0 && timeout <= 3600.0))
    throw py::value_error("timeout must lie in (0, 3600] s of simulated time");
  AutopilotOptions o;
  o.timeout = timeout;
  return o;
}

}  // namespace

void bindAutopilot(py::module_& m) {
  py::class_<PyAutopilot>(m, "Autopilot",
                          "The clinician's technique to a named vessel, from what the screen shows")
      .def(py::init([](std::shared_ptr<PyModel> model, const PyData& data, const std::string& target,
                       const std::string& device, double timeout) {
             requireCompatible(*model, data);
             return PyAutopilot{model, Autopilot(data.model(), data.data, target, device,
                                                 optionsOf(timeout))};
           }),
           py::arg("model"), py::arg("data"), py::arg("target"), py::arg("device") = "",
           py::arg("timeout") = 90.0,
           "Raises LoadError for a target it refuses (unknown, not connected, too narrow)")
      .def(
          "control",
          [](PyAutopilot& a, const PyModel& model, PyData& data) {
            requireCompatible(model, data);
            return a.pilot.control(data.model(), &data.data);
          },
          py::arg("model"), py::arg("data"),
          "Sets the drive commands for the next steps (call before each step); a line when "
          "the phase changes")
      .def("observe", [](PyAutopilot& a, const PyData& data, bool failed) { a.pilot.observe(data.data, failed); },
           py::arg("data"), py::arg("step_failed") = false, "After each step: its outcome")
      .def_property_readonly("done", [](const PyAutopilot& a) { return a.pilot.done(); })
      .def_property_readonly("phase", [](const PyAutopilot& a) { return std::string(phaseName(a.pilot.phase())); })
      .def_property_readonly("report", [](const PyAutopilot& a) { return reportOf(a.pilot.report()); },
                             "reached, reason, time [s], retries, peak_wall_force [N], "
                             "failed_steps, remaining_path [m]");

  m.def(
      "run_autopilot",
      [](const PyModel& model, PyData& data, const std::string& target, const std::string& device,
         double timeout) {
        requireCompatible(model, data);
        const AutopilotOptions o = optionsOf(timeout);
        AutopilotReport r;
        {
          py::gil_scoped_release release;
          r = runAutopilot(data.model(), &data.data, target, device, o);
        }
        return reportOf(r);
      },
      py::arg("model"), py::arg("data"), py::arg("target"), py::arg("device") = "",
      py::arg("timeout") = 90.0,
      "Runs the autopilot to a vessel as `evsim navigate` does (GIL released); its report");
}

}  // namespace evsim::python
