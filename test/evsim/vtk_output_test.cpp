// `evsim run --vtk` and `evsim mesh --out X.vtp`, read back with VTK's own
// reader: the frames hold the devices where an in-process run of the same
// scene has them, the contacts with their forces, a .pvd series ParaView
// opens, and the surface mesh.
#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

vtkSmartPointer<vtkPolyData> readVtp(const std::string& path) {
  auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  r->SetFileName(path.c_str());
  r->Update();
  return r->GetOutput();
}

TEST(VtkOutput, FramesHoldTheRunsDevicesAndContacts) {
  const fs::path dir = fs::temp_directory_path() / "evsim_vtk_output_test";
  fs::remove_all(dir);
  // carotid at 6 s: the wire in the arch, pressing on the wall.
  const std::string command = std::string(EVSIM_EVSIM_BINARY) + " run carotid --steps 6000 --vtk " +
                              dir.string() + " --vtk-rate 2 > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const SceneModel model = loadScene("carotid");
  SimData data = makeData(model);
  for (int k = 0; k < 6000; ++k) ASSERT_EQ(step(model, &data), StepStatus::kOk);

  const auto devices = readVtp((dir / "devices_0006000.vtp").string());
  ASSERT_EQ(devices->GetNumberOfPoints(), static_cast<vtkIdType>(data.devices[0].position.size()));
  EXPECT_EQ(devices->GetNumberOfLines(), 1);
  double worst = 0.0;
  for (vtkIdType i = 0; i < devices->GetNumberOfPoints(); ++i) {
    double p[3];
    devices->GetPoint(i, p);
    worst = std::max(worst, (Vec3(p[0], p[1], p[2]) - data.devices[0].position[i]).norm());
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_DOUBLE_EQ(devices->GetPointData()->GetArray("radius")->GetTuple1(0),
                   model.devices[0].node_radius[0]);

  const auto contacts = readVtp((dir / "contacts_0006000.vtp").string());
  ASSERT_EQ(contacts->GetNumberOfPoints(), static_cast<vtkIdType>(data.contacts.size()));
  ASSERT_GT(data.contacts.size(), 0u);
  double total = 0.0, written = 0.0;
  for (size_t c = 0; c < data.contacts.size(); ++c) {
    total += data.contacts[c].force;
    written += contacts->GetPointData()->GetArray("normal_force")->GetTuple1(c);
  }
  EXPECT_GT(total, 0.0);
  EXPECT_NEAR(written, total, 1e-12);

  std::ifstream pvd(dir / "devices.pvd");
  std::stringstream text;
  text << pvd.rdbuf();
  EXPECT_NE(text.str().find("timestep=\"6\" part=\"0\" file=\"devices_0006000.vtp\""),
            std::string::npos)
      << text.str();
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(dir))
    frames += entry.path().filename().string().rfind("devices_", 0) == 0;
  EXPECT_EQ(frames, 13);  // t = 0, 0.5, ..., 6 s
  fs::remove_all(dir);
}

TEST(VtkOutput, TheSurfaceMeshAsVtp) {
  const fs::path out = fs::temp_directory_path() / "evsim_vtk_output_test_surface.vtp";
  const std::string command = std::string(EVSIM_EVSIM_BINARY) + " mesh aneurysm --out " +
                              out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const auto mesh = readVtp(out.string());
  EXPECT_GT(mesh->GetNumberOfPolys(), 1000);
  ASSERT_NE(mesh->GetPointData()->GetNormals(), nullptr);
  // Every vertex on the wall: the field is zero there, up to the mesher's
  // linear interpolation on its lattice (a quarter of the thinnest radius).
  const SceneModel model = loadScene("aneurysm");
  double worst = 0.0;
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); i += 97) {
    double p[3];
    mesh->GetPoint(i, p);
    const FieldSample g = model.surface->evaluate(Vec3(p[0], p[1], p[2]), 0.0);
    worst = std::max(worst, std::abs(g.value) / g.gradient.norm());
  }
  EXPECT_LT(worst, 0.1e-3);
  fs::remove(out);
}

}  // namespace
}  // namespace evsim
