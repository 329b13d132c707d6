// A patient's centreline from a VTK PolyData file (VMTK `vmtkcenterlines`,
// SimVascular): `.vtp` (XML: ascii, binary, zlib-compressed, appended) or
// legacy `.vtk`, read by VTK's own readers. Declared and documented in
// endovascular_sim/scene/centerline_vtk.h.
#include "endovascular_sim/scene/centerline_vtk.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkGenericDataObjectReader.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkXMLFileReadTester.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "endovascular_sim/core/file_path.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/patient_frame.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw LoadError(path, 0, "vessels.centerline", why);
}

/// The file's PolyData, read by VTK's reader for its kind (its messages
/// silenced: every failure is reported here).
vtkSmartPointer<vtkPolyData> readPolyData(const std::string& path) {
  if (!fs::is_regular_file(path)) fail(path, "no such file");
  if (fs::file_size(path) == 0) fail(path, "the file is empty");
  const bool warnings = vtkObject::GetGlobalWarningDisplay();
  vtkObject::GlobalWarningDisplayOff();
  vtkSmartPointer<vtkPolyData> out;
  std::string why;
  if (lowerCaseExtension(path) == ".vtp") {
    auto tester = vtkSmartPointer<vtkXMLFileReadTester>::New();
    tester->SetFileName(path.c_str());
    if (!tester->TestReadFile()) {
      why = "not a VTK XML file";
    } else if (std::string(tester->GetFileDataType()) != "PolyData") {
      why = std::string("a VTK XML file of type ") + tester->GetFileDataType() +
            ", not PolyData (a centreline is PolyData with lines)";
    } else {
      auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
      reader->SetFileName(path.c_str());
      reader->Update();
      if (reader->GetErrorCode() != 0 || !reader->GetOutput())
        why = "VTK's XML reader could not read it (damaged or truncated data)";
      else
        out = reader->GetOutput();
    }
  } else {
    auto reader = vtkSmartPointer<vtkGenericDataObjectReader>::New();
    reader->SetFileName(path.c_str());
    if (!reader->OpenVTKFile() || !reader->ReadHeader()) {
      why = "not a legacy VTK file";
    } else {
      reader->CloseVTKFile();
      reader->Update();
      if (!reader->IsFilePolyData())
        why = "a legacy VTK file of another dataset type, not POLYDATA";
      else if (reader->GetErrorCode() != 0 || !reader->GetPolyDataOutput())
        why = "VTK's legacy reader could not read it (damaged or truncated data)";
      else
        out = reader->GetPolyDataOutput();
    }
  }
  vtkObject::SetGlobalWarningDisplay(warnings);
  if (!why.empty()) fail(path, why);
  return out;
}

/// The first of the branch-id arrays the file has, per cell (-1: none).
std::vector<int> branchIds(vtkPolyData* data, const std::vector<vtkIdType>& cells) {
  for (const char* name : {"BranchId", "GroupIds", "CenterlineIds"}) {
    if (vtkDataArray* a = data->GetCellData()->GetArray(name)) {
      std::vector<int> ids;
      for (vtkIdType c : cells) ids.push_back(static_cast<int>(a->GetTuple1(c)));
      return ids;
    }
    if (vtkDataArray* a = data->GetPointData()->GetArray(name)) {
      std::vector<int> ids;
      auto points = vtkSmartPointer<vtkIdList>::New();
      for (vtkIdType c : cells) {
        data->GetCellPoints(c, points);
        std::map<int, int> votes;
        for (vtkIdType k = 0; k < points->GetNumberOfIds(); ++k) {
          const int v = static_cast<int>(a->GetTuple1(points->GetId(k)));
          if (v >= 0) ++votes[v];
        }
        int id = -1, most = 0;
        for (auto [v, n] : votes)
          if (n > most) id = v, most = n;
        ids.push_back(id);
      }
      return ids;
    }
  }
  return {};
}

/// A cell-data array of one component, or null.
vtkDataArray* cellArray(vtkPolyData* data, const char* name) {
  vtkDataArray* a = data->GetCellData()->GetArray(name);
  return a && a->GetNumberOfComponents() == 1 ? a : nullptr;
}

/// `vmtkbranchextractor`'s output: each centreline cut into tracts (cells
/// with CenterlineIds and TractIds, each with its own points, consecutive
/// tracts meeting at an interpolated split point), the tracts of one vessel
/// grouped across centrelines by GroupIds, a bifurcation's tracts marked by
/// Blanking. Reassembles one line per centreline (layout a), each point
/// with its tract's group (-1 blanked or no groups). False when the file
/// has no tracts.
bool reassembleTracts(vtkPolyData* data, const std::vector<vtkIdType>& cells,
                      const std::string& path, CenterlinePolylines* out) {
  vtkDataArray* centerline = cellArray(data, "CenterlineIds");
  vtkDataArray* tract = cellArray(data, "TractIds");
  if (!centerline || !tract) return false;
  vtkDataArray* group = cellArray(data, "GroupIds");
  vtkDataArray* blanking = cellArray(data, "Blanking");
  std::map<int, std::map<int, size_t>> tracts;  // centreline -> tract -> line
  for (size_t l = 0; l < cells.size(); ++l) {
    const int c = static_cast<int>(centerline->GetTuple1(cells[l]));
    const int t = static_cast<int>(tract->GetTuple1(cells[l]));
    if (!tracts[c].emplace(t, l).second)
      fail(path, "centreline " + std::to_string(c) + " has two tracts " + std::to_string(t) +
                     " (CenterlineIds, TractIds)");
  }
  std::vector<std::vector<int>> lines;
  std::vector<int> ids;
  out->point_group.assign(out->points.size(), -1);
  for (const auto& [c, by_tract] : tracts) {
    std::vector<int> line;
    for (const auto& [t, l] : by_tract) {
      const std::vector<int>& cell = out->lines[l];
      if (cell.empty()) continue;
      const bool blanked = blanking && blanking->GetTuple1(cells[l]) != 0.0;
      const int g = group && !blanked ? static_cast<int>(group->GetTuple1(cells[l])) : -1;
      size_t from = 0;
      if (!line.empty()) {
        const double gap = (out->points[cell[0]] - out->points[line.back()]).norm();
        const double r = out->radius[line.back()];
        if (gap > r) {
          std::ostringstream why;
          why << "centreline " << c << ": tract " << t << " starts " << gap / r
              << " radii from where the one before it ends (the tracts of a centreline follow "
                 "each other)";
          fail(path, why.str());
        }
        from = gap <= 1e-3 * r ? 1 : 0;  // the split point, written by both tracts
      }
      for (size_t k = from; k < cell.size(); ++k) {
        line.push_back(cell[k]);
        out->point_group[cell[k]] = g;
      }
      ++out->tracts;
    }
    lines.push_back(line);
    ids.push_back(c);
  }
  out->lines = lines;
  out->branch_id = ids;
  return true;
}

}  // namespace

bool isVtkCenterlinePath(const std::string& path) {
  const std::string e = lowerCaseExtension(path);
  return e == ".vtp" || e == ".vtk";
}

CenterlinePolylines readVtkPolylines(const std::string& path, const VtkCenterlineOptions& o) {
  const vtkSmartPointer<vtkPolyData> data = readPolyData(path);
  const vtkIdType n = data->GetNumberOfPoints();
  if (n == 0) fail(path, "the PolyData has no points");
  vtkDataArray* radius = data->GetPointData()->GetArray(o.radius_array.c_str());
  if (!radius || radius->GetNumberOfComponents() != 1) {
    std::string present;
    for (int i = 0; i < data->GetPointData()->GetNumberOfArrays(); ++i) {
      const char* name = data->GetPointData()->GetArrayName(i);
      present += std::string(present.empty() ? "" : ", ") + (name ? name : "(unnamed)");
    }
    fail(path, "no point-data array '" + o.radius_array + "' of one component (the radius; set " +
                   "vessels.radius_array); its point arrays: " +
                   (present.empty() ? std::string("none") : present));
  }
  CenterlinePolylines out;
  out.points.resize(n);
  out.radius.resize(n);
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    data->GetPoint(i, p);
    out.points[i] = o.unit * Vec3(p[0], p[1], p[2]);
    out.radius[i] = o.unit * radius->GetTuple1(i);
  }
  vtkCellArray* lines = data->GetLines();
  if (!lines || lines->GetNumberOfCells() == 0)
    fail(path, "the PolyData has no lines (a centreline is made of polyline cells; it has " +
                   std::to_string(data->GetNumberOfPolys()) + " polygons, " +
                   std::to_string(data->GetNumberOfVerts()) + " vertices)");
  // Line cells come after the vertex cells in the PolyData's cell ids.
  const vtkIdType first_line = data->GetNumberOfVerts();
  std::vector<vtkIdType> cells;
  auto ids = vtkSmartPointer<vtkIdList>::New();
  lines->InitTraversal();
  for (vtkIdType c = 0; lines->GetNextCell(ids); ++c) {
    std::vector<int> line;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      line.push_back(static_cast<int>(ids->GetId(k)));
    out.lines.push_back(line);
    cells.push_back(first_line + c);
  }
  out.branch_id = branchIds(data, cells);
  // The anatomical frame, when the file declares it: a field-data string
  // array `frame` holding an orientation code (LPS, RAS, ...).
  if (auto* frame = vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray("frame"))) {
    if (frame->GetNumberOfValues() < 1) fail(path, "its field-data array 'frame' is empty");
    out.frame = frame->GetValue(0);
    const std::string why = frameCodeProblem(out.frame);
    if (!why.empty()) fail(path, "field-data array 'frame': " + why);
  }
  // Radius checks before the tracts are joined (their gaps are in radii).
  for (vtkIdType i = 0; i < n; ++i)
    if (!(std::isfinite(out.radius[i]) && out.radius[i] > 0.0)) return out;
  reassembleTracts(data, cells, path, &out);
  return out;
}

Centerline loadVtkCenterline(const std::string& path, const VtkCenterlineOptions& o,
                             CenterlineTreeReport* report) {
  const CenterlinePolylines lines = readVtkPolylines(path, o);
  try {
    Centerline c = buildCenterlineTree(lines, o.tree, report);
    c.frame = lines.frame;
    return c;
  } catch (const std::invalid_argument& e) {
    fail(path, e.what());
  }
}

}  // namespace evsim
