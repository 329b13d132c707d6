// `evsim vessels SCENE`: the scene's vessel tree as the simulator builds it
// (for a VTK centreline: the branch ids its `names:` map, what the
// simplification kept), the surface's fidelity to the radii, and the cost of
// one field evaluation at the scene's first device.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <random>

#include "commands.h"
#include "endovascular_sim/geometry/surface_fidelity.h"
#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/scene/centerline_vtk.h"
#include "endovascular_sim/scene/scene_file.h"
#include "scene_source.h"

namespace evsim {
namespace {

/// Nanoseconds per field evaluation at points inside the lumen (within 0.8
/// radii of the centreline), for a device of radius r [m].
double evaluationCost(const VesselField& field, const Centerline& c, double r) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3> points;
  for (int k = 0; k < 20000; ++k) {
    const int i = static_cast<int>(rng() % c.numPoints());
    Vec3 offset(unit(rng), unit(rng), unit(rng));
    points.push_back(c.position[i] + 0.8 * c.radius[i] * offset / std::max(1.0, offset.norm()));
  }
  double sink = 0.0;
  const int rounds = 20;
  const auto t0 = std::chrono::steady_clock::now();
  for (int round = 0; round < rounds; ++round)
    for (const Vec3& p : points) sink += field.evaluate(p, r).value;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (sink == 42.0) std::cout << "";  // keeps the loop
  return s * 1e9 / (rounds * points.size());
}

void printFigures(const char* where, const FidelityFigures& f) {
  std::printf("  %-36s median %5.2f %%, worst %6.2f %% (%d rays)\n", where, 100.0 * f.median,
              100.0 * f.worst, f.rays);
}

}  // namespace

int vesselsCommand(const std::string& scene, const CenterlineSource& centerline) {
  const SceneSpec spec = sceneSpecOf(scene, centerline);
  if (!spec.vessels.present) {
    std::cerr << "evsim: scene '" << spec.name << "' has no vessels\n";
    return kExitBadInput;
  }
  const VesselSpec& v = spec.vessels;
  std::vector<std::string> warnings;
  const Centerline c = buildCenterline(v, &warnings);
  const bool vtk = isVtkCenterlinePath(v.centerline_file);
  std::printf("scene %s: vessels from %s\n", spec.name.c_str(), v.centerline_file.c_str());
  CenterlineTreeReport report;
  if (vtk) {
    loadVtkCenterline(v.centerline_file, {v.units, v.radius_array, v.tree}, &report);
    std::printf(
        "  file: %d points, %s -> tree of %d branches, %d points; simplified to axis <= %.3f mm, "
        "radius <= %.2f %% (tolerances %.3f mm, %.1f %%)\n",
        report.file_points,
        report.tracts > 0
            ? (std::to_string(report.tracts) + " tracts joined per centreline, merged" +
               (report.grouped ? " by their groups" : ""))
                  .c_str()
        : report.overlapping ? "one polyline per outlet (merged)"
                             : "a merged tree of line cells",
        report.branches, report.points, report.max_axis_error * 1e3,
        100.0 * report.max_radius_error, v.tree.tolerance * 1e3, 100.0 * v.tree.radius_tolerance);
  }
  const VesselAtlas atlas(c);
  std::printf("  %-28s %6s  %-28s %11s %11s\n", "vessel", vtk ? "branch" : "", "branches off",
              "length [mm]", "min r [mm]");
  for (size_t i = 0; i < atlas.vessels().size(); ++i) {
    const NamedVessel& n = atlas.vessels()[i];
    const std::string id =
        vtk && i < report.branch_ids.size() ? std::to_string(report.branch_ids[i]) : "";
    std::printf("  %-28s %6s  %-28s %11.1f %11.2f\n", n.name.c_str(), id.c_str(),
                n.parent >= 0 ? atlas.vessels()[n.parent].name.c_str() : "(inlet)", n.length * 1e3,
                n.radius * 1e3);
  }
  const VesselField field(c, v.aneurysms, {}, v.field);
  // The tree's own surface: an aneurysm's dome is no radius of it.
  const SurfaceFidelity f = measureSurfaceFidelity(VesselField(c, {}, {}, v.field), c);
  std::printf("surface lumen radius against the centreline's (aneurysms left out):\n");
  printFigures("along the vessels:", f.along);
  printFigures("within two radii of forks and ends:", f.at_forks);
  const double r =
      spec.devices.empty() ? 0.0 : spec.devices[0].device.sections[0].section.outer_radius;
  std::printf("field evaluation: %.0f ns at a device of radius %.3f mm (%d segments)\n",
              evaluationCost(field, c, r), r * 1e3, field.numSegments());
  for (const std::string& w : warnings) std::printf("warning: %s\n", w.c_str());
  return kExitOk;
}

}  // namespace evsim
