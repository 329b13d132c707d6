// A generated arch as a patient's files. Declared and documented in
// endovascular_sim/scene/arch_scene.h.
#include "endovascular_sim/scene/arch_scene.h"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/scene/centerline_vtk.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

/// The generated vessel a point lies on (the nearest centreline point's).
std::string nearestVessel(const Centerline& c, const Vec3& p) {
  int best = 0;
  for (int i = 1; i < c.numPoints(); ++i)
    if ((c.position[i] - p).squaredNorm() < (c.position[best] - p).squaredNorm()) best = i;
  return c.vessel_names[c.vessel[best]];
}

/// Branch id -> name for the .vtp as the scene's loader reads it (rooted at
/// its widest end, the aortic root, as a patient's file is by default):
/// each branch named after the generated vessel at its middle.
std::map<int, std::string> branchNames(const Centerline& generated, const std::string& vtp) {
  CenterlineTreeReport report;
  const Centerline read = loadVtkCenterline(vtp, {}, &report);
  std::map<int, std::string> names;
  for (size_t v = 0; v < read.vessel_names.size(); ++v) {
    std::vector<int> points;
    for (int i = 0; i < read.numPoints(); ++i)
      if (read.vessel[i] == static_cast<int>(v)) points.push_back(i);
    if (points.empty()) continue;
    names[report.branch_ids[v]] =
        nearestVessel(generated, read.position[points[points.size() / 2]]);
  }
  return names;
}

std::string catheterFile(const std::string& catheter) {
  return configDirectory() + "/devices/" +
         (catheter == "catheter" ? std::string("catheter") : catheter + "_catheter") + ".urdf";
}

}  // namespace

void writeVmtkCenterline(const Centerline& c, const std::string& path) {
  std::vector<char> has_child(c.numPoints(), 0);
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.parent[i] >= 0) has_child[c.parent[i]] = 1;
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto radius = vtkSmartPointer<vtkDoubleArray>::New();
  radius->SetName("MaximumInscribedSphereRadius");
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  for (int leaf = 0; leaf < c.numPoints(); ++leaf) {
    if (has_child[leaf] || c.parent[leaf] < 0) continue;
    std::vector<int> chain;  // root -> leaf
    for (int i = leaf; i >= 0; i = c.parent[i]) chain.insert(chain.begin(), i);
    lines->InsertNextCell(static_cast<vtkIdType>(chain.size()));
    for (int i : chain) {
      const Vec3 x = 1e3 * c.position[i];
      lines->InsertCellPoint(points->InsertNextPoint(x.x(), x.y(), x.z()));
      radius->InsertNextValue(1e3 * c.radius[i]);
    }
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetLines(lines);
  data->GetPointData()->AddArray(radius);
  if (!c.frame.empty()) {
    auto frame = vtkSmartPointer<vtkStringArray>::New();
    frame->SetName("frame");
    frame->InsertNextValue(c.frame);
    data->GetFieldData()->AddArray(frame);
  }
  auto writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
  writer->SetFileName(path.c_str());
  writer->SetInputData(data);
  writer->SetDataModeToBinary();
  if (!writer->Write()) throw LoadError(path, 0, "", "cannot write the centreline file");
}

ArchScenes writeArchScenes(const ArchParameters& p, const std::string& dir) {
  fs::create_directories(dir);
  const Centerline c = archCenterline(p);
  const std::string stem = "arch_" + std::to_string(p.seed);
  ArchScenes out;
  out.centerline = (fs::path(dir) / (stem + ".vtp")).string();
  writeVmtkCenterline(c, out.centerline);
  // The femoral access: the descending aorta, 4 cm above its end (its
  // straight part, 13 cm below the arch's end).
  const int desc = [&] {
    for (size_t v = 0; v < c.vessel_names.size(); ++v)
      if (c.vessel_names[v] == "descending_aorta") return static_cast<int>(v);
    return -1;
  }();
  Vec3 bottom = Vec3::Zero();
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.vessel[i] == desc) bottom = c.position[i];
  const Vec3 access = bottom + Vec3(0.0, 0.0, 0.04);
  const std::map<int, std::string> names = branchNames(c, out.centerline);
  std::map<std::string, std::vector<std::string>> targets_of;  // catheter -> targets
  for (const std::string& t : archTargets(p)) targets_of[archCatheter(p, t)].push_back(t);
  for (const auto& [catheter, targets] : targets_of) {
    const std::string scene = (fs::path(dir) / (stem + "_" + catheter + ".yaml")).string();
    std::ofstream f(scene);
    f << "# A generated arch (evsim arch --seed " << p.seed << "): " << p.summary() << ".\n"
      << "# Its centreline " << stem << ".vtp is written as VMTK writes one; the names\n"
      << "# below map the branch ids the loader finds (evsim vessels " << stem
      << ".vtp --units mm).\n"
      << "name: " << stem << "_" << catheter << "\n"
      << "description: A generated aortic arch (" << p.summary() << "), a guidewire in a "
      << catheter << " at the femoral access.\n"
      << "time_step: 0.001\nduration: 90\neffects: [gravity, subdivision, coaxial]\n"
      << "gravity: supine\nvessels:\n  centerline: " << stem << ".vtp\n  units: mm\n"
      << "  names:\n";
    for (const auto& [id, name] : names) f << "    " << id << ": " << name << "\n";
    f << "devices:\n  - file: " << catheterFile(catheter) << "\n    access_point: [" << access.x()
      << ", " << access.y() << ", " << access.z() << "]\n"
      << "    insertion_direction: [0.0, 0.0, 1.0]\n    up: [0.0, 1.0, 0.0]\n"
      << "    inserted_length: 0.08\n"
      << "  - file: " << configDirectory() << "/devices/guidewire.urdf\n    inside: "
      << (catheter == "catheter" ? "catheter" : catheter) << "\n    inserted_length: 0.10\n"
      << "targets:\n";
    for (const std::string& t : targets) f << "  - {vessel: " << t << ", device: guidewire}\n";
    if (!f) throw LoadError(scene, 0, "", "cannot write the scene file");
    out.catheter_scene[catheter] = scene;
    for (const std::string& t : targets) out.target_scene[t] = scene;
  }
  return out;
}

}  // namespace evsim
