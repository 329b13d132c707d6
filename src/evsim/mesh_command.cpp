// `evsim mesh`: the vessel surface of a scene as a triangle mesh file.
#include <chrono>
#include <iostream>

#include "commands.h"
#include "endovascular_sim/geometry/surface_mesh.h"
#include "endovascular_sim/scene/scene_file.h"
#include "output_paths.h"
#include "vtk_output.h"

namespace evsim {

int meshScene(const MeshOptions& o) {
  const std::string writable = checkWritableFile(o.out);
  if (!writable.empty()) {
    std::cerr << "evsim: --out: " << writable << "\n";
    return kExitBadInput;
  }
  const SceneSpec spec = loadSceneFile(resolveScenePath(o.scene));
  if (!spec.vessels.present) {
    std::cerr << "evsim: scene '" << spec.name << "' has no vessels\n";
    return kExitBadInput;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const VesselField field = buildVesselField(spec.vessels, false);
  const SurfaceMesh mesh = meshVesselSurface(field, o.spacing, o.device_radius);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::string why;
  const bool vtp = o.out.size() > 4 && o.out.compare(o.out.size() - 4, 4, ".vtp") == 0;
  if (!(vtp ? writeSurfaceVtp(mesh, o.out, &why) : writeMesh(mesh, o.out, &why))) {
    std::cerr << "evsim: " << why << "\n";
    return kExitFailure;
  }
  std::cout << o.out << ": " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
            << " triangles from " << field.numSegments() << " segments in " << s << " s\n";
  return kExitOk;
}

}  // namespace evsim
