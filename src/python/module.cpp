// endovascular_sim._core: the ROS-free core as a Python module (pybind11).
// The Python names are the core's (SceneModel, SimData, step, ...), the
// arrays view the core's memory, the loops stay in C++ with the GIL
// released. The pure-Python package endovascular_sim re-exports it.
#include <pybind11/pybind11.h>

#include "endovascular_sim/core/load_error.h"
#include "py_simulation.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "The endovascular_sim core: scenes, simulation data, steps, autopilot, X-ray";
  // A malformed scene, device, vessel or state file: ValueError's subclass,
  // its message "file:line: field: what" (file, line, field as attributes).
  static py::exception<evsim::LoadError> load_error(m, "LoadError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const evsim::LoadError& e) {
      py::object error = py::handle(load_error.ptr())(e.what());
      error.attr("file") = e.file();
      error.attr("line") = e.line();
      error.attr("field") = e.field();
      PyErr_SetObject(load_error.ptr(), error.ptr());
    }
  });
  evsim::python::bindModel(m);
  evsim::python::bindData(m);
  evsim::python::bindStep(m);
  evsim::python::bindAutopilot(m);
  evsim::python::bindImaging(m);
  evsim::python::bindRollout(m);
  evsim::python::bindAnatomy(m);
}
