// What evsim writes for ParaView, with VTK's own XML writer (binary, zlib).
// Declared and documented in vtk_output.h.
#include "vtk_output.h"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataWriter.h>

#include <cstdio>
#include <fstream>

namespace evsim {
namespace {

vtkSmartPointer<vtkDoubleArray> doubles(const char* name, int components) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  return a;
}

bool writePolyData(vtkPolyData* data, const std::string& path, std::string* why) {
  auto w = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
  w->SetFileName(path.c_str());
  w->SetInputData(data);
  w->SetDataModeToBinary();
  w->SetCompressorTypeToZLib();
  if (w->Write() == 1) return true;
  *why = "cannot write " + path;
  return false;
}

bool writePvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames,
              std::string* why) {
  std::ofstream out(path);
  out.precision(12);
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& [time, file] : frames)
    out << "    <DataSet timestep=\"" << time << "\" part=\"0\" file=\"" << file << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  if (out) return true;
  *why = "cannot write " + path;
  return false;
}

}  // namespace

bool writeSurfaceVtp(const SurfaceMesh& mesh, const std::string& path, std::string* why) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto normals = doubles("Normals", 3);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& p = mesh.vertices[i];
    points->InsertNextPoint(p.x(), p.y(), p.z());
    normals->InsertNextTuple3(mesh.normals[i].x(), mesh.normals[i].y(), mesh.normals[i].z());
  }
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& t : mesh.triangles) {
    const vtkIdType ids[3] = {t(0), t(1), t(2)};
    polys->InsertNextCell(3, ids);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetPolys(polys);
  data->GetPointData()->SetNormals(normals);
  return writePolyData(data, path, why);
}

bool VtkSeries::write(const SceneModel& model, const SimData& data, std::string* why) {
  char name[64];
  auto time = doubles("TimeValue", 1);
  time->InsertNextValue(data.time);

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto radius = doubles("radius", 1);
  auto velocity = doubles("velocity", 3);
  auto device = vtkSmartPointer<vtkIntArray>::New();
  device->SetName("device");
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  for (size_t d = 0; d < data.devices.size(); ++d) {
    const DeviceState& s = data.devices[d];
    std::vector<vtkIdType> ids;
    for (size_t n = 0; n < s.position.size(); ++n) {
      ids.push_back(
          points->InsertNextPoint(s.position[n].x(), s.position[n].y(), s.position[n].z()));
      radius->InsertNextValue(model.devices[d].node_radius[n]);
      velocity->InsertNextTuple3(s.velocity[n].x(), s.velocity[n].y(), s.velocity[n].z());
      device->InsertNextValue(static_cast<int>(d));
    }
    lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  auto devices = vtkSmartPointer<vtkPolyData>::New();
  devices->SetPoints(points);
  devices->SetLines(lines);
  devices->GetPointData()->AddArray(radius);
  devices->GetPointData()->AddArray(velocity);
  devices->GetPointData()->AddArray(device);
  devices->GetFieldData()->AddArray(time);
  std::snprintf(name, sizeof(name), "devices_%07ld.vtp", data.step);
  if (!writePolyData(devices, folder_ + "/" + name, why)) return false;
  devices_.push_back({data.time, name});

  auto at = vtkSmartPointer<vtkPoints>::New();
  at->SetDataTypeToDouble();
  auto normal = doubles("normal", 3), force = doubles("force", 3);
  auto normal_force = doubles("normal_force", 1), gap = doubles("gap", 1);
  auto of = vtkSmartPointer<vtkIntArray>::New();
  of->SetName("device");
  auto verts = vtkSmartPointer<vtkCellArray>::New();
  for (const Contact& c : data.contacts) {
    const vtkIdType id = at->InsertNextPoint(c.point.x(), c.point.y(), c.point.z());
    verts->InsertNextCell(1, &id);
    normal->InsertNextTuple3(c.normal.x(), c.normal.y(), c.normal.z());
    const Vec3 f = c.force * c.normal + c.friction;
    force->InsertNextTuple3(f.x(), f.y(), f.z());
    normal_force->InsertNextValue(c.force);
    gap->InsertNextValue(c.gap);
    of->InsertNextValue(c.device);
  }
  auto contacts = vtkSmartPointer<vtkPolyData>::New();
  contacts->SetPoints(at);
  contacts->SetVerts(verts);
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(normal), static_cast<vtkDataArray*>(force),
                          static_cast<vtkDataArray*>(normal_force), static_cast<vtkDataArray*>(gap),
                          static_cast<vtkDataArray*>(of)})
    contacts->GetPointData()->AddArray(a);
  contacts->GetFieldData()->AddArray(time);
  std::snprintf(name, sizeof(name), "contacts_%07ld.vtp", data.step);
  if (!writePolyData(contacts, folder_ + "/" + name, why)) return false;
  contacts_.push_back({data.time, name});
  return true;
}

bool VtkSeries::finish(std::string* why) const {
  return writePvd(folder_ + "/devices.pvd", devices_, why) &&
         writePvd(folder_ + "/contacts.pvd", contacts_, why);
}

}  // namespace evsim
