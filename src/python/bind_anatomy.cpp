// Generated anatomy: write_arch, the arches of `evsim arch`
// (geometry/arch_generator.h, scene/arch_scene.h) from Python.
#include <pybind11/stl.h>

#include "endovascular_sim/scene/arch_scene.h"
#include "py_simulation.h"

namespace evsim::python {

void bindAnatomy(py::module_& m) {
  m.def(
      "write_arch",
      [](std::uint64_t seed, const std::string& folder, int type, int bovine, int aberrant) {
        if (type < 0 || type > 3) throw py::value_error("type must be 0 (drawn) or 1-3");
        if (bovine < -1 || bovine > 1 || aberrant < -1 || aberrant > 1)
          throw py::value_error("bovine and aberrant_subclavian: -1 drawn, 0 never, 1 always");
        ArchDrawOptions o;
        o.type = type;
        o.bovine = bovine;
        o.aberrant_rsa = aberrant;
        ArchParameters p;
        ArchScenes files;
        {
          py::gil_scoped_release release;
          p = drawArch(seed, o);
          files = writeArchScenes(p, folder);
        }
        py::dict out;
        out["seed"] = seed;
        out["summary"] = p.summary();
        out["type"] = static_cast<int>(p.type);
        out["bovine"] = p.bovine;
        out["aberrant_subclavian"] = p.aberrant_rsa;
        out["centerline"] = files.centerline;
        out["scenes"] = files.catheter_scene;
        out["target_scenes"] = files.target_scene;
        out["targets"] = archTargets(p);
        return out;
      },
      py::arg("seed"), py::arg("folder"), py::arg("type") = 0, py::arg("bovine") = -1,
      py::arg("aberrant_subclavian") = -1,
      "Draws an aortic arch from published statistics (docs/patient_anatomy.md, 'Generated "
      "arches') and writes it into `folder` as `evsim arch` does: the VMTK-style .vtp and a "
      "scene per catheter. Returns its seed, summary, type (1-3), bovine, aberrant_subclavian, "
      "centerline, scenes (catheter -> scene file), target_scenes (target -> scene file), "
      "targets.");
}

}  // namespace evsim::python
