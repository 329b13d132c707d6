// SceneModel: a loaded scene (immutable), what it holds, and its pickling.
#include <pybind11/stl.h>

#include <filesystem>

#include "endovascular_sim/scene/scene_file.h"
#include "py_simulation.h"

namespace evsim::python {

std::shared_ptr<PyModel> loadModel(const std::string& name_or_path) {
  auto m = std::make_shared<PyModel>();
  m->source = name_or_path;
  {
    py::gil_scoped_release release;  // a network scene builds for a second
    m->model = std::make_shared<const SceneModel>(loadScene(name_or_path));
  }
  return m;
}

std::shared_ptr<PyModel> loadModelText(const std::string& text, const std::string& path) {
  auto m = std::make_shared<PyModel>();
  m->source = path;
  m->text = text;
  m->from_text = true;
  {
    py::gil_scoped_release release;
    m->model = std::make_shared<const SceneModel>(buildSceneModel(loadSceneText(text, path)));
  }
  return m;
}

int deviceIndex(const SceneModel& model, const py::handle& device) {
  const int n = static_cast<int>(model.devices.size());
  if (py::isinstance<py::int_>(device)) {
    const long i = device.cast<long>();
    if (i >= 0 && i < n) return static_cast<int>(i);
  } else if (py::isinstance<py::str>(device)) {
    const int i = findDevice(model, device.cast<std::string>());
    if (i >= 0) return i;
  }
  std::string names;
  for (const DeviceModel& d : model.devices) names += (names.empty() ? "" : ", ") + d.name;
  throw py::value_error("no device " + py::repr(device).cast<std::string>() + " in scene '" +
                        model.name + "' (its devices: " + names + ", or their indices 0.." +
                        std::to_string(n - 1) + ")");
}

namespace {

py::list effectNames(const EffectSet& e) {
  py::list names;
  const std::pair<bool, const char*> all[] = {
      {e.gravity, "gravity"},   {e.vessel_motion, "vessel_motion"}, {e.device_contact, "device_contact"},
      {e.subdivision, "subdivision"}, {e.friction, "friction"}, {e.coaxial, "coaxial"},
      {e.blood_drag, "blood_drag"}, {e.vessel_deformation, "vessel_deformation"}};
  for (const auto& [on, name] : all)
    if (on) names.append(name);
  return names;
}

py::dict deviceInfo(const SceneModel& m, size_t i) {
  const DeviceModel& d = m.devices[i];
  py::dict info;
  info["name"] = d.name;
  info["num_nodes"] = d.num_nodes;
  info["length"] = d.length;
  info["radius"] = d.node_radius.empty() ? 0.0 : d.node_radius.back();
  info["max_insertion_speed"] = d.max_insertion_speed;
  info["max_rotation_speed"] = d.max_rotation_speed;
  const int outer = i < m.outer_of.size() ? m.outer_of[i] : -1;
  info["outer"] = outer >= 0 ? py::cast(m.devices[outer].name) : py::none();
  info["max_force"] = m.drive_specs[i].max_force;
  info["max_torque"] = m.drive_specs[i].max_torque;
  return info;
}

py::dict targetInfo(const SceneModel& m, const Target& t) {
  py::dict info;
  info["vessel"] = t.spec.vessel.empty() ? py::none() : py::cast(t.spec.vessel);
  info["aneurysm"] = t.spec.aneurysm >= 0 ? py::cast(t.spec.aneurysm) : py::none();
  info["device"] = t.device >= 0 ? py::cast(m.devices[t.device].name) : py::none();
  info["depth"] = t.spec.depth;
  info["dwell"] = t.spec.dwell;
  return info;
}

}  // namespace

void bindModel(py::module_& m) {
  py::class_<PyModel, std::shared_ptr<PyModel>>(m, "SceneModel",
                                                "A loaded scene: immutable, shared by its SimData")
      .def_property_readonly("name", [](const PyModel& p) { return p.get().name; })
      .def_property_readonly("file", [](const PyModel& p) { return p.get().file; },
                             "The scene file (for a scene from text: the path it stands for)")
      .def_property_readonly("time_step", [](const PyModel& p) { return p.get().time_step; },
                             "[s] of one step")
      .def_property_readonly("duration", [](const PyModel& p) { return p.get().duration; },
                             "[s] of the scripted procedure")
      .def_property_readonly("effects", [](const PyModel& p) { return effectNames(p.get().effects); })
      .def_property_readonly("gravity",
                             [](const PyModel& p) {
                               const Vec3& g = p.get().gravity;
                               return py::make_tuple(g.x(), g.y(), g.z());
                             },
                             "[m/s^2] (zero unless the effect 'gravity' is on)")
      .def_property_readonly("devices",
                             [](const PyModel& p) {
                               py::list out;
                               for (size_t i = 0; i < p.get().devices.size(); ++i)
                                 out.append(deviceInfo(p.get(), i));
                               return out;
                             },
                             "Per device: name, num_nodes, length [m], radius [m] at the tip, "
                             "max_insertion_speed [m/s], max_rotation_speed [rad/s], outer "
                             "device, drive limits max_force [N] and max_torque [N m]")
      .def_property_readonly("device_names",
                             [](const PyModel& p) {
                               std::vector<std::string> names;
                               for (const DeviceModel& d : p.get().devices) names.push_back(d.name);
                               return names;
                             })
      .def_property_readonly("vessel_names",
                             [](const PyModel& p) {
                               std::vector<std::string> names;
                               if (p.get().atlas)
                                 for (const NamedVessel& v : p.get().atlas->vessels())
                                   names.push_back(v.name);
                               return names;
                             },
                             "The named vessels (empty in free space)")
      .def("vessel",
           [](const PyModel& p, const std::string& name) {
             const SceneModel& s = p.get();
             const int v = s.atlas ? s.atlas->find(name) : -1;
             if (v < 0) {
               std::string near;
               if (s.atlas)
                 for (const std::string& c : s.atlas->closestNames(name))
                   near += (near.empty() ? "" : ", ") + c;
               throw py::value_error("no vessel '" + name + "' in scene '" + s.name + "'" +
                                     (near.empty() ? " (it has no vessels)" : " (nearest: " + near + ")"));
             }
             const NamedVessel& nv = s.atlas->vessels()[v];
             py::dict info;
             info["name"] = nv.name;
             info["parent"] = nv.parent >= 0 ? py::cast(s.atlas->vessels()[nv.parent].name) : py::none();
             info["generation"] = nv.generation;
             info["length"] = nv.length;
             info["radius"] = nv.radius;
             py::list children;
             for (int c : nv.children) children.append(s.atlas->vessels()[c].name);
             info["children"] = children;
             return info;
           },
           py::arg("name"),
           "A named vessel: parent, generation, length [m], smallest radius [m], children")
      .def("vessel_point",
           [](const PyModel& p, const std::string& name, double depth) {
             const SceneModel& s = p.get();
             const int v = s.atlas ? s.atlas->find(name) : -1;
             if (v < 0) throw py::value_error("no vessel '" + name + "' in scene '" + s.name + "'");
             const Vec3 x = s.atlas->pointAt(v, depth);
             return py::make_tuple(x.x(), x.y(), x.z());
           },
           py::arg("name"), py::arg("depth"),
           "The point [m] on a vessel's centreline `depth` [m] past its origin")
      .def("vessel_path",
           [](const PyModel& p, const std::string& from, const std::string& to) {
             const SceneModel& s = p.get();
             const int a = s.atlas ? s.atlas->find(from) : -1, b = s.atlas ? s.atlas->find(to) : -1;
             if (a < 0 || b < 0)
               throw py::value_error("no vessel '" + (a < 0 ? from : to) + "' in scene '" + s.name + "'");
             std::vector<std::string> names;
             for (int v : s.atlas->path(a, b)) names.push_back(s.atlas->vessels()[v].name);
             return names;
           },
           py::arg("from_vessel"), py::arg("to_vessel"),
           "The vessels from one to another through the tree (empty: not connected)")
      .def_property_readonly("targets",
                             [](const PyModel& p) {
                               py::list out;
                               for (const Target& t : p.get().targets) out.append(targetInfo(p.get(), t));
                               return out;
                             })
      .def_property_readonly("warnings", [](const PyModel& p) { return p.get().warnings; })
      .def(py::pickle(
          [](const PyModel& p) { return py::make_tuple(p.source, p.text, p.from_text); },
          [](const py::tuple& t) {
            if (t.size() != 3) throw py::value_error("not a pickled SceneModel");
            const auto source = t[0].cast<std::string>();
            return t[2].cast<bool>() ? loadModelText(t[1].cast<std::string>(), source)
                                     : loadModel(source);
          }))
      .def("__repr__", [](const PyModel& p) {
        return "<endovascular_sim.SceneModel '" + p.get().name + "' (" +
               std::to_string(p.get().devices.size()) + " devices)>";
      });

  m.def("load_scene", &loadModel, py::arg("name_or_path"),
        "A shipped scene by name, or a scene file (raises LoadError naming file, line and key)");
  m.def(
      "load_scene_text",
      [](const std::string& text, const std::string& path) {
        const std::string stands_for =
            path.empty() ? (std::filesystem::path(configDirectory()) / "scenes" / "<text>.yaml").string()
                         : path;
        return loadModelText(text, stands_for);
      },
      py::arg("text"), py::arg("path") = "",
      "A scene from YAML text; `path` stands for its file (its folder resolves relative paths; "
      "default: a file among the shipped scenes, so '../devices/guidewire.urdf' works)");
  m.def("shipped_scenes", &shippedScenes, "Names of the shipped scenes");
  m.def("config_directory", &configDirectory, "Folder of the shipped devices/, scenes/, vessels/");
}

}  // namespace evsim::python
