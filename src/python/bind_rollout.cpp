// rollout(): a batch of simulations stepped by the core's thread pool from
// an (N x T x 2·devices) array of commands.
#include <pybind11/stl.h>

#include <set>

#include "endovascular_sim/sim/rollout.h"
#include "py_simulation.h"

namespace evsim::python {

namespace {

template <typename T>
py::array_t<T> arrayOf(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

}  // namespace

void bindRollout(py::module_& m) {
  m.def(
      "rollout",
      [](py::object models, const std::vector<PyData*>& data, py::array commands_in,
         long steps_per_command, int nthread, bool recover) {
        if (data.empty()) throw py::value_error("rollout needs at least one SimData");
        std::vector<const PyModel*> owners;
        if (py::isinstance<PyModel>(models)) {
          owners.push_back(&models.cast<const PyModel&>());
        } else {
          for (py::handle h : models) owners.push_back(&h.cast<const PyModel&>());
          if (owners.size() != data.size())
            throw py::value_error(std::to_string(owners.size()) + " models for " +
                                  std::to_string(data.size()) + " simulations");
        }
        std::set<const PyData*> distinct(data.begin(), data.end());
        if (distinct.size() != data.size())
          throw py::value_error("a SimData appears twice in the batch (copy.deepcopy it)");
        std::vector<const SceneModel*> scenes;
        for (size_t n = 0; n < data.size(); ++n) {
          const PyModel& owner = *owners[owners.size() == 1 ? 0 : n];
          requireCompatible(owner, *data[n]);
          if (owners.size() > 1 || n == 0) scenes.push_back(&data[n]->model());
        }
        const py::ssize_t nd = static_cast<py::ssize_t>(scenes.front()->devices.size());
        if (!py::isinstance<py::array>(commands_in) ||
            !(commands_in.dtype().kind() == 'f' || commands_in.dtype().kind() == 'i'))
          throw py::value_error("commands must be a numeric numpy array (N x T x " +
                                std::to_string(2 * nd) + ")");
        auto commands = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(commands_in);
        if (commands.ndim() != 3 || commands.shape(0) != static_cast<py::ssize_t>(data.size()) ||
            commands.shape(2) != 2 * nd)
          throw py::value_error(
              "commands must have shape (N, T, 2 * devices) = (" + std::to_string(data.size()) +
              ", T, " + std::to_string(2 * nd) + "): per device its insertion velocity [m/s] and "
              "rotation velocity [rad/s]; got ndim " + std::to_string(commands.ndim()));
        if (nthread < 1) throw py::value_error("nthread must be at least 1");
        std::vector<SimData*> sims;
        for (PyData* p : data) sims.push_back(&p->data);
        const long horizon = static_cast<long>(commands.shape(1));
        const std::string why = checkRollout(scenes, sims, commands.data(), horizon, steps_per_command);
        if (!why.empty()) throw py::value_error(why);
        RolloutOutput out;
        {
          py::gil_scoped_release release;
          out = rollout(scenes, sims, commands.data(), horizon, steps_per_command, nthread, recover);
        }
        const py::ssize_t N = out.batch, T = out.horizon, D = out.devices;
        py::dict r;
        r["time"] = arrayOf(out.time, {N, T});
        r["node_position"] = arrayOf(out.node_position, {N, T, out.nodes, 3});
        r["tip_position"] = arrayOf(out.tip_position, {N, T, D, 3});
        r["inserted_length"] = arrayOf(out.inserted_length, {N, T, D});
        r["rotation_angle"] = arrayOf(out.rotation_angle, {N, T, D});
        r["drive_force"] = arrayOf(out.drive_force, {N, T, D});
        r["peak_drive_force"] = arrayOf(out.peak_drive_force, {N, T, D});
        r["tip_vessel"] = arrayOf(out.tip_vessel, {N, T, D});
        r["max_wall_force"] = arrayOf(out.max_wall_force, {N, T});
        r["failed"] = arrayOf(out.failed, {N, T}).attr("astype")("bool");
        return r;
      },
      py::arg("model"), py::arg("data"), py::arg("commands"), py::arg("steps_per_command") = 1,
      py::arg("nthread") = 1, py::arg("recover") = true,
      "Steps each SimData (in place) through its commands, (N x T x 2·devices) per device "
      "insertion [m/s] and rotation [rad/s] velocities, each held `steps_per_command` steps, "
      "on `nthread` threads (GIL released). `model`: one SceneModel or one per SimData. "
      "Returns arrays after each command: time (N x T) [s], node_position (N x T x nodes x 3) "
      "[m], tip_position (N x T x devices x 3) [m], inserted_length and rotation_angle "
      "(N x T x devices) [m], [rad], drive_force (N x T x devices) [N], tip_vessel (vessel "
      "indices of model.vessel_names), max_wall_force (N x T) [N], failed (N x T): a "
      "simulation whose step failed stops there (SimData.last_error says why).");
}

}  // namespace evsim::python
