// The Python front's objects: a scene's model with where it came from (so
// that it pickles), and a simulation's data holding its model alive (so
// that a SimData alone pickles, deep-copies and is stepped by a rollout).
// The bindings (module.cpp and bind_*.cpp) adapt the core's own names.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "endovascular_sim/sim/simulation.h"

namespace evsim::python {

namespace py = pybind11;

/// A loaded scene: the core's immutable SceneModel, and its source.
struct PyModel {
  std::shared_ptr<const SceneModel> model;
  std::string source;     // the name or path it was loaded from, or the path its text stands for
  std::string text;       // the YAML text, when loaded from text
  bool from_text{false};  // loaded from `text` (else from `source`)
  const SceneModel& get() const { return *model; }
};

/// A simulation's data and the model it was made for.
struct PyData {
  std::shared_ptr<const PyModel> owner;
  SimData data;
  const SceneModel& model() const { return owner->get(); }
};

/// Loads a model from a name or path (LoadError on failure).
std::shared_ptr<PyModel> loadModel(const std::string& name_or_path);
/// Loads a model from YAML text standing for the file at `path`.
std::shared_ptr<PyModel> loadModelText(const std::string& text, const std::string& path);

/// Throws ValueError unless `data` was made for a model of `model`'s scene
/// (its name, devices and node counts).
void requireCompatible(const PyModel& model, const PyData& data);

/// Index of a device given by name or index (ValueError naming the devices).
int deviceIndex(const SceneModel& model, const py::handle& device);

/// A read-only numpy view of `count` rows of `columns` doubles at `first`
/// (row stride `stride` bytes), alive as long as `owner` is.
py::array_t<double> viewRows(const double* first, size_t count, size_t columns, size_t stride,
                             const py::handle& owner);

// The parts of the module, each in its own file.
void bindModel(py::module_& m);
void bindData(py::module_& m);
void bindStep(py::module_& m);
void bindAutopilot(py::module_& m);
void bindImaging(py::module_& m);
void bindRollout(py::module_& m);
void bindAnatomy(py::module_& m);

}  // namespace evsim::python
