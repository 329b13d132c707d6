// SimData: a simulation's state as numpy views of the core's own arrays,
// its contacts, tips and statistics, copies and pickles.
#include <pybind11/stl.h>

#include "endovascular_sim/sim/state_file.h"
#include "endovascular_sim/sim/step_json.h"
#include "py_simulation.h"

namespace evsim::python {

py::array_t<double> viewRows(const double* first, size_t count, size_t columns, size_t stride,
                             const py::handle& owner) {
  py::array_t<double> a({count, columns}, {stride, sizeof(double)}, first, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

void requireCompatible(const PyModel& model, const PyData& data) {
  const SceneModel& m = model.get();
  const SceneModel& d = data.model();
  bool same = &m == &d || (m.name == d.name && m.devices.size() == d.devices.size());
  for (size_t i = 0; same && &m != &d && i < m.devices.size(); ++i)
    same = m.devices[i].num_nodes == d.devices[i].num_nodes;
  if (!same)
    throw py::value_error("this SimData was made for scene '" + d.name + "', not for '" + m.name +
                          "' (make_data(model) makes one for it)");
}

namespace {

/// One device's state in a SimData, its arrays viewing the data's memory.
struct DeviceView {
  py::object owner;  // the PyData
  int index{0};
  PyData& data() const { return owner.cast<PyData&>(); }
  const DeviceState& state() const { return data().data.devices[index]; }
};

py::array_t<double> vec3Rows(const std::vector<Vec3>& v, const py::handle& owner) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
  return viewRows(v.empty() ? nullptr : v.front().data(), v.size(), 3, sizeof(Vec3), owner);
}

py::dict tipOf(const PyData& p, int i) {
  const SimData& d = p.data;
  const SceneModel& m = p.model();
  const DeviceState& s = d.devices[i];
  py::dict tip;
  tip["device"] = m.devices[i].name;
  const Vec3& x = s.position.back();
  const Quat& q = s.rotation.back();
  tip["position"] = py::make_tuple(x.x(), x.y(), x.z());
  tip["orientation"] = py::make_tuple(q.x(), q.y(), q.z(), q.w());
  if (m.atlas && static_cast<size_t>(i) < d.tips.size()) {
    const VesselLocation& at = d.tips[i];
    tip["vessel"] = m.atlas->vessels()[at.vessel].name;
    tip["depth"] = at.depth;
    tip["in_lumen"] = at.inside;
  } else {
    tip["vessel"] = py::none();
  }
  if (static_cast<size_t>(i) < d.drives.size()) {
    const DriveWrench& w = d.drives[i];
    tip["proximal_force"] = py::make_tuple(w.force.x(), w.force.y(), w.force.z());
    tip["proximal_moment"] = py::make_tuple(w.moment.x(), w.moment.y(), w.moment.z());
    tip["drive_force"] = w.axial_force;
    tip["drive_torque"] = w.axial_torque;
    const Vec3& f = d.tip_forces[i];
    tip["tip_force"] = py::make_tuple(f.x(), f.y(), f.z());
  }
  tip["drive_stalled"] =
      static_cast<size_t>(i) < d.stalls.size() && d.stalls[i].against_command;
  return tip;
}

py::dict contactsOf(const SimData& d) {
  const size_t k = d.contacts.size();
  py::array_t<double> point({k, size_t{3}}), normal({k, size_t{3}}), friction({k, size_t{3}});
  py::array_t<double> force(k), gap(k);
  py::array_t<int> device(k), other(k);
  py::array_t<bool> lumen(k);
  auto p = point.mutable_unchecked<2>(), n = normal.mutable_unchecked<2>(),
       fr = friction.mutable_unchecked<2>();
  auto f = force.mutable_unchecked<1>(), g = gap.mutable_unchecked<1>();
  auto dv = device.mutable_unchecked<1>(), o = other.mutable_unchecked<1>();
  auto l = lumen.mutable_unchecked<1>();
  for (size_t i = 0; i < k; ++i) {
    const Contact& c = d.contacts[i];
    for (int j = 0; j < 3; ++j) {
      p(i, j) = c.point(j);
      n(i, j) = c.normal(j);
      fr(i, j) = c.friction(j);
    }
    f(i) = c.force;
    g(i) = c.gap;
    dv(i) = c.device;
    o(i) = c.other_device;
    l(i) = c.lumen;
  }
  py::dict out;
  out["point"] = point;
  out["normal"] = normal;
  out["force"] = force;
  out["gap"] = gap;
  out["friction"] = friction;
  out["device"] = device;
  out["other_device"] = other;
  out["lumen"] = lumen;
  return out;
}

/// Replaces the data's state by `fresh`, node arrays copied into their
/// storage (views stay valid).
void assignData(SimData fresh, SimData* data) {
  std::vector<DeviceState> devices;
  devices.swap(data->devices);
  for (size_t i = 0; i < devices.size(); ++i) copyState(fresh.devices[i], &devices[i]);
  *data = std::move(fresh);
  data->devices.swap(devices);
}

py::object pickleModel(const PyModel& m) {
  return py::make_tuple(m.source, m.text, m.from_text);
}

}  // namespace

void bindData(py::module_& m) {
  py::class_<DeviceView>(m, "DeviceState", "One device's state; arrays are read-only views")
      .def_property_readonly("name",
                             [](const DeviceView& v) { return v.data().model().devices[v.index].name; })
      .def_property_readonly("position",
                             [](const DeviceView& v) { return vec3Rows(v.state().position, v.owner); },
                             "(nodes x 3) [m], world")
      .def_property_readonly("rotation",
                             [](const DeviceView& v) {
                               const auto& r = v.state().rotation;
                               static_assert(sizeof(Quat) == 4 * sizeof(double), "packed quaternion");
                               return viewRows(r.empty() ? nullptr : r.front().coeffs().data(),
                                               r.size(), 4, sizeof(Quat), v.owner);
                             },
                             "(nodes x 4) node frames as unit quaternions (x, y, z, w), world")
      .def_property_readonly("velocity",
                             [](const DeviceView& v) { return vec3Rows(v.state().velocity, v.owner); },
                             "(nodes x 3) [m/s]")
      .def_property_readonly(
          "angular_velocity",
          [](const DeviceView& v) { return vec3Rows(v.state().angular_velocity, v.owner); },
          "(nodes x 3) [rad/s], world")
      .def_property_readonly("inserted_length",
                             [](const DeviceView& v) { return v.state().inserted_length; },
                             "[m] past the access point")
      .def_property_readonly("rotation_angle",
                             [](const DeviceView& v) { return v.state().rotation_angle; },
                             "[rad] the proximal rotation")
      .def_property_readonly("released", [](const DeviceView& v) { return v.state().released; },
                             "detached (a coil): no longer driven");

  py::class_<PyData>(m, "SimData", "A simulation's state, of one SceneModel")
      .def_property_readonly("model", [](const PyData& p) { return p.owner; })
      .def_property_readonly("time", [](const PyData& p) { return p.data.time; }, "[s]")
      .def_property_readonly("step", [](const PyData& p) { return p.data.step; }, "steps taken")
      .def_property_readonly("asleep", [](const PyData& p) { return p.data.asleep; })
      .def_property_readonly("last_error", [](const PyData& p) { return p.data.last_error; },
                             "why the last failed step was rejected")
      .def_property_readonly("devices",
                             [](py::object self) {
                               py::list out;
                               const int n = static_cast<int>(self.cast<PyData&>().data.devices.size());
                               for (int i = 0; i < n; ++i) out.append(DeviceView{self, i});
                               return out;
                             })
      .def_property_readonly("tips",
                             [](const PyData& p) {
                               py::list out;
                               for (size_t i = 0; i < p.data.devices.size(); ++i)
                                 out.append(tipOf(p, static_cast<int>(i)));
                               return out;
                             },
                             "Per device: tip position [m] and orientation (x, y, z, w), the "
                             "vessel it is in and how deep [m], the drive's proximal force [N] "
                             "and moment [N m], drive_force [N] and drive_torque [N m] along "
                             "the insertion axis, tip_force [N] (contacts on its last 5 mm), "
                             "drive_stalled")
      .def_property_readonly("contacts", [](const PyData& p) { return contactsOf(p.data); },
                             "The last step's contacts: point [m], normal, force [N], gap [m], "
                             "friction [N], device, other_device (-1: the wall), lumen")
      .def_property_readonly("max_wall_force", [](const PyData& p) { return maxWallForce(p.data); },
                             "[N] the largest wall contact force of the last step")
      .def_property_readonly("stats",
                             [](const PyData& p) {
                               return py::module_::import("json").attr("loads")(
                                   stepJson(p.model(), p.data));
                             },
                             "The last step's statistics: the names and units of `evsim run --json`")
      .def("stats_json", [](const PyData& p) { return stepJson(p.model(), p.data); },
           "The last step as `evsim run --json` prints it")
      .def_property_readonly("targets",
                             [](const PyData& p) {
                               py::list out;
                               for (size_t k = 0; k < p.model().targets.size(); ++k) {
                                 const TargetProgress t =
                                     k < p.data.targets.size() ? p.data.targets[k] : TargetProgress{};
                                 py::dict d;
                                 d["label"] = p.model().targets[k].spec.label();
                                 d["reached"] = t.reached;
                                 d["reached_time"] = t.reached_time;
                                 d["best_depth"] = t.best_depth;
                                 out.append(d);
                               }
                               return out;
                             })
      .def("take_notices",
           [](PyData& p) {
             std::vector<std::string> n;
             n.swap(p.data.notices);
             return n;
           },
           "The notices since the last call (scripted commands refused, drives at a limit)")
      .def("__copy__", [](const PyData& p) { return PyData{p.owner, p.data}; })
      .def("__deepcopy__", [](const PyData& p, py::dict) { return PyData{p.owner, p.data}; })
      .def(py::pickle(
          [](const PyData& p) {
            return py::make_tuple(pickleModel(*p.owner), stateText(p.model(), p.data));
          },
          [](const py::tuple& t) {
            if (t.size() != 2) throw py::value_error("not a pickled SimData");
            const py::tuple src = t[0].cast<py::tuple>();
            const auto source = src[0].cast<std::string>();
            std::shared_ptr<const PyModel> owner =
                src[2].cast<bool>() ? loadModelText(src[1].cast<std::string>(), source)
                                    : loadModel(source);
            PyData p{owner, makeData(owner->get())};
            loadStateText(owner->get(), t[1].cast<std::string>(), "<pickled SimData>", &p.data);
            return p;
          }))
      .def("__repr__", [](const PyData& p) {
        return "<endovascular_sim.SimData of '" + p.model().name +
               "' at t = " + std::to_string(p.data.time) + " s>";
      });

  m.def(
      "make_data",
      [](std::shared_ptr<PyModel> model) { return PyData{model, makeData(model->get())}; },
      py::arg("model"), "Fresh data at the scene's initial state");
  m.def(
      "reset_data",
      [](const PyModel& model, PyData& data) {
        requireCompatible(model, data);
        assignData(makeData(data.model()), &data.data);
      },
      py::arg("model"), py::arg("data"),
      "Puts the data back at the scene's initial state (its arrays' views stay valid)");
  m.def(
      "save_state",
      [](const PyModel& model, const PyData& data, const std::string& path) {
        requireCompatible(model, data);
        if (!saveState(data.model(), data.data, path))
          throw py::value_error("cannot write the state file '" + path + "'");
      },
      py::arg("model"), py::arg("data"), py::arg("path"),
      "Writes the state as `evsim run --save-state` does");
  m.def(
      "load_state",
      [](const PyModel& model, PyData& data, const std::string& path) {
        requireCompatible(model, data);
        loadState(data.model(), path, &data.data);
      },
      py::arg("model"), py::arg("data"), py::arg("path"),
      "Reads a state file into the data (LoadError naming line and field; the data then unchanged)");
  m.def(
      "state_text",
      [](const PyModel& model, const PyData& data) {
        requireCompatible(model, data);
        return stateText(data.model(), data.data);
      },
      py::arg("model"), py::arg("data"), "The state file's text");
  m.def(
      "load_state_text",
      [](const PyModel& model, PyData& data, const std::string& text) {
        requireCompatible(model, data);
        loadStateText(data.model(), text, "<state text>", &data.data);
      },
      py::arg("model"), py::arg("data"), py::arg("text"), "load_state from a state file's text");
}

}  // namespace evsim::python
