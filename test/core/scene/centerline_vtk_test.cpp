// Patient centrelines from VTK files, written here by VTK itself: a known
// Y (a 60 mm trunk of 6 mm radius splitting into branches of 3 and 2.5 mm)
// in both layouts found in the wild (one polyline per outlet from the
// inlet; a merged tree of 2-point lines with BranchId), in mm and cm, in
// every XML data mode and the legacy format. The tree, its radii and the
// surface built on it are checked against the known geometry; bad files
// against the message they must give.
#include "endovascular_sim/scene/centerline_vtk.h"

#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "vtk_centerline_fixture.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;
using namespace vtk_y;  // NOLINT: the Y's helpers

struct FileOptions {
  bool overlapping{true};  // layout (a); else (b) with BranchId
  double scale{1.0};       // file units per mm (0.1: cm)
  bool with_radius{true};
  double radius_noise{0.0};    // relative, uniform
  bool extra_piece{false};     // a separate 5 mm line
  std::string mode{"binary"};  // ascii, binary (zlib), appended, raw, legacy
};

vtkSmartPointer<vtkPolyData> makeY(const FileOptions& f) {
  std::vector<Sampled> lines;
  if (f.overlapping) {
    // Each line from the inlet; the second's trunk jittered by 10 um, as
    // two VMTK centrelines along one path are.
    Sampled left, right;
    sample(kInlet, kFork, kTrunkR, kTrunkR, 0.3, true, &left);
    sample(kFork, kLeft, kLeftR, kLeftR, 0.3, false, &left);
    sample(kInlet, kFork, kTrunkR, kTrunkR, 0.3, true, &right);
    for (Vec3& p : right.x) p.x() += 0.01;
    sample(kFork, kRight, kRightR, kRightR, 0.3, false, &right);
    lines = {left, right};
  } else {
    Sampled trunk, left, right;
    sample(kInlet, kFork, kTrunkR, kTrunkR, 0.3, true, &trunk);
    sample(kFork, kLeft, kLeftR, kLeftR, 0.3, true, &left);
    sample(kFork, kRight, kRightR, kRightR, 0.3, true, &right);
    lines = {trunk, left, right};
  }
  if (f.extra_piece) {
    Sampled piece;
    sample(Vec3(40, 0, 0), Vec3(45, 0, 0), 1.0, 1.0, 0.5, true, &piece);
    lines.push_back(piece);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-f.radius_noise, f.radius_noise);
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto radius = vtkSmartPointer<vtkDoubleArray>::New();
  radius->SetName("MaximumInscribedSphereRadius");
  auto other = vtkSmartPointer<vtkDoubleArray>::New();
  other->SetName("Abscissas");
  auto branch = vtkSmartPointer<vtkIntArray>::New();
  branch->SetName("BranchId");
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  vtkIdType fork_id = -1;
  for (size_t l = 0; l < lines.size(); ++l) {
    std::vector<vtkIdType> ids;
    for (size_t k = 0; k < lines[l].x.size(); ++k) {
      const Vec3 p = f.scale * lines[l].x[k];
      // Layout (b): the branches start at the trunk's last point id.
      if (!f.overlapping && l > 0 && l < 3 && k == 0) {
        ids.push_back(fork_id);
        continue;
      }
      ids.push_back(points->InsertNextPoint(p.x(), p.y(), p.z()));
      radius->InsertNextValue(f.scale * lines[l].r[k] * (1.0 + noise(rng)));
      other->InsertNextValue(static_cast<double>(k));
    }
    if (!f.overlapping && l == 0) fork_id = ids.back();
    if (f.overlapping) {
      cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
      continue;
    }
    for (size_t k = 1; k < ids.size(); ++k) {  // 2-point lines, as SimVascular writes
      const vtkIdType pair[2] = {ids[k - 1], ids[k]};
      cells->InsertNextCell(2, pair);
      branch->InsertNextValue(static_cast<int>(l));
    }
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetLines(cells);
  if (f.with_radius) data->GetPointData()->AddArray(radius);
  data->GetPointData()->AddArray(other);
  if (!f.overlapping) data->GetCellData()->AddArray(branch);
  return data;
}

TEST(CenterlineVtk, BothLayoutsInEveryDataModeGiveTheY) {
  for (bool overlapping : {true, false})
    for (const char* mode : {"ascii", "binary", "appended", "raw", "legacy"}) {
      FileOptions f;
      f.overlapping = overlapping;
      f.mode = mode;
      const std::string name = std::string(overlapping ? "a_" : "b_") + mode;
      const std::string path = write(makeY(f), name, mode);
      CenterlineTreeReport report;
      const Centerline c = load(path, 1e-3, &report);
      EXPECT_EQ(report.overlapping, overlapping) << name;
      expectTheY(c, report, name);
      fs::remove(path);
    }
}

TEST(CenterlineVtk, CentimetresAreScaledAsDeclared) {
  FileOptions f;
  f.scale = 0.1;  // SimVascular: cm
  const std::string path = write(makeY(f), "cm", "binary");
  CenterlineTreeReport report;
  expectTheY(load(path, 1e-2, &report), report, "cm");
  fs::remove(path);
}

TEST(CenterlineVtk, OutletIndicesAndBranchIdsNameTheVessels) {
  // Layout (a): a branch ending at an outlet takes its line's index.
  FileOptions a;
  const std::string pa = write(makeY(a), "names_a", "binary");
  CenterlineTreeOptions names;
  names.names = {{0, "left_branch"}, {1, "right_branch"}};
  CenterlineTreeReport report;
  const Centerline ca = load(pa, 1e-3, &report, names);
  VesselAtlas atlas(ca);
  EXPECT_EQ(atlas.locate(1e-3 * Vec3(-15, 0, 90)).vessel, atlas.find("left_branch"));
  EXPECT_EQ(atlas.locate(1e-3 * Vec3(15, 0, 90)).vessel, atlas.find("right_branch"));
  EXPECT_EQ(atlas.vessels()[atlas.locate(1e-3 * Vec3(0, 0, 30)).vessel].name, "branch_2");
  // Layout (b): the file's BranchId (trunk 0, left 1, right 2).
  FileOptions b;
  b.overlapping = false;
  const std::string pb = write(makeY(b), "names_b", "binary");
  names.names = {{0, "trunk"}, {1, "left_branch"}, {2, "right_branch"}};
  const Centerline cb = load(pb, 1e-3, &report, names);
  VesselAtlas atlas_b(cb);
  EXPECT_EQ(atlas_b.locate(1e-3 * Vec3(0, 0, 30)).vessel, atlas_b.find("trunk"));
  EXPECT_EQ(atlas_b.locate(1e-3 * Vec3(15, 0, 90)).vessel, atlas_b.find("right_branch"));
  // A name for a branch the tree does not have.
  names.names = {{7, "nowhere"}};
  try {
    load(pb, 1e-3, &report, names);
    ADD_FAILURE() << "a name for branch 7 was accepted";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("no branch 7"), std::string::npos) << e.what();
  }
  fs::remove(pa);
  fs::remove(pb);
}

TEST(CenterlineVtk, NoisyRadiiAreSmoothedAndTheSurfaceKeepsThem) {
  FileOptions f;
  f.radius_noise = 0.08;
  const std::string path = write(makeY(f), "noisy", "binary");
  CenterlineTreeReport report;
  const Centerline c = load(path, 1e-3, &report);
  EXPECT_LT(c.numPoints(), 200);
  // The lumen of the convolution surface around the axis, away from the
  // fork and the ends (two radii), against the known radius.
  const VesselField field(c, {}, {}, {});
  std::vector<double> errors;
  struct Leg {
    Vec3 a, b;
    double r;
  };
  for (const Leg& leg :
       {Leg{kInlet, kFork, kTrunkR}, Leg{kFork, kLeft, kLeftR}, Leg{kFork, kRight, kRightR}}) {
    const Vec3 axis = (leg.b - leg.a).normalized();
    const double len = (leg.b - leg.a).norm();
    for (double s = 2.0 * kTrunkR; s <= len - 2.0 * leg.r; s += 1.0) {
      const Vec3 p = 1e-3 * (leg.a + s * axis);
      for (int k = 0; k < 4; ++k) {
        const Vec3 out = Eigen::AngleAxisd(k * M_PI / 2.0, axis) * axis.unitOrthogonal();
        const SurfacePoint w = firstRoot(field, p, p + 3e-3 * leg.r * out, 0.0);
        ASSERT_TRUE(w.hit);
        errors.push_back(std::abs((w.point - p).norm() - 1e-3 * leg.r) / (1e-3 * leg.r));
      }
    }
  }
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], worst = errors.back();
  std::printf(
      "[ metric   ] lumen radius of the surface against the file's: median %.2f %%, "
      "worst %.2f %% (%zu rays, radius noise 8 %%)\n",
      100 * median, 100 * worst, errors.size());
  EXPECT_LT(median, 0.05);
  EXPECT_LT(worst, 0.15);
  fs::remove(path);
}

TEST(CenterlineVtk, ADisconnectedPieceIsDroppedWithAWarning) {
  FileOptions f;
  f.overlapping = false;
  f.extra_piece = true;
  const std::string path = write(makeY(f), "pieces", "binary");
  CenterlineTreeReport report;
  const Centerline c = load(path, 1e-3, &report);
  expectTheY(c, report, "pieces");
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("dropped: 11 points (5 mm)"), std::string::npos)
      << report.warnings[0];
  fs::remove(path);
}

TEST(CenterlineVtk, TheSimplifiedWallStaysWithinTheTolerances) {
  // The noisy Y simplified with the default tolerances against the same file
  // kept whole (tolerances far below its noise): the lumen radius along the
  // same rays moves by less than tolerance + radius_tolerance * r.
  FileOptions f;
  f.radius_noise = 0.08;
  const std::string path = write(makeY(f), "simplified", "binary");
  CenterlineTreeReport report;
  CenterlineTreeOptions whole;
  whole.tolerance = 1e-7;
  whole.radius_tolerance = 1e-4;
  const Centerline fine = load(path, 1e-3, &report, whole);
  const Centerline coarse = load(path, 1e-3, &report);
  ASSERT_GT(fine.numPoints(), 5 * coarse.numPoints());
  const VesselField a(fine, {}, {}, {}), b(coarse, {}, {}, {});
  const CenterlineTreeOptions o;
  double worst = 0.0;  // [relative to the bound]
  for (int i = 0; i < fine.numPoints(); i += 7) {
    const int j = fine.parent[i];
    if (j < 0) continue;
    const Vec3 p = 0.5 * (fine.position[i] + fine.position[j]);
    const double r = fine.radius[i];
    if ((p - 1e-3 * kFork).norm() < 3.0 * 1e-3 * kTrunkR || (p - 1e-3 * kInlet).norm() < 2.0 * r ||
        (p - 1e-3 * kLeft).norm() < 2.0 * r || (p - 1e-3 * kRight).norm() < 2.0 * r)
      continue;
    const Vec3 u = (fine.position[i] - fine.position[j]).normalized();
    for (int k = 0; k < 4; ++k) {
      const Vec3 out = Eigen::AngleAxisd(k * M_PI / 2.0, u) * u.unitOrthogonal();
      const SurfacePoint wa = firstRoot(a, p, p + 3.0 * r * out, 0.0);
      const SurfacePoint wb = firstRoot(b, p, p + 3.0 * r * out, 0.0);
      ASSERT_TRUE(wa.hit && wb.hit);
      const double bound = o.tolerance + o.radius_tolerance * r;
      worst = std::max(worst, (wa.point - wb.point).norm() / bound);
    }
  }
  std::printf(
      "[ metric   ] simplification: %d -> %d points; the wall moves by at most %.2f of "
      "tolerance + radius_tolerance * r\n",
      fine.numPoints(), coarse.numPoints(), worst);
  EXPECT_LT(worst, 1.0);
  fs::remove(path);
}

TEST(CenterlineVtk, BranchesWhoseLumensOverlapAreWarned) {
  // A merged tree (layout b) whose two branches leave the fork 2 mm apart and
  // run parallel: radii of 3 mm reach the other branch's centreline.
  Sampled trunk, left, right;
  sample(kInlet, kFork, kTrunkR, kTrunkR, 0.3, true, &trunk);
  sample(kFork, kFork + Vec3(-1, 0, 5), 3.0, 3.0, 0.3, true, &left);
  sample(kFork + Vec3(-1, 0, 5), Vec3(-1, 0, 100), 3.0, 3.0, 0.3, false, &left);
  sample(kFork, kFork + Vec3(1, 0, 5), 3.0, 3.0, 0.3, true, &right);
  sample(kFork + Vec3(1, 0, 5), Vec3(1, 0, 100), 3.0, 3.0, 0.3, false, &right);
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto radius = vtkSmartPointer<vtkDoubleArray>::New();
  radius->SetName("MaximumInscribedSphereRadius");
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  vtkIdType fork = -1;
  for (const Sampled* line : {&trunk, &left, &right}) {
    std::vector<vtkIdType> ids;
    for (size_t k = 0; k < line->x.size(); ++k) {
      if (line != &trunk && k == 0) {
        ids.push_back(fork);
        continue;
      }
      ids.push_back(points->InsertNextPoint(line->x[k].x(), line->x[k].y(), line->x[k].z()));
      radius->InsertNextValue(line->r[k]);
    }
    if (line == &trunk) fork = ids.back();
    cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetLines(cells);
  data->GetPointData()->AddArray(radius);
  const std::string path = write(data, "crowded", "binary");
  CenterlineTreeReport report;
  load(path, 1e-3, &report);
  bool warned = false;
  for (const std::string& w : report.warnings)
    warned = warned || w.find("their lumens merge") != std::string::npos;
  EXPECT_TRUE(warned) << (report.warnings.empty() ? "no warning" : report.warnings[0]);
  fs::remove(path);
}

/// The file must be refused with a message holding `expect`.
void expectRefused(const std::string& path, const std::string& expect, double unit = 1e-3) {
  CenterlineTreeReport report;
  try {
    load(path, unit, &report);
    ADD_FAILURE() << path << " was accepted";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), path);
  }
}

TEST(CenterlineVtk, BadFilesAreRefusedSayingWhatIsWrong) {
  FileOptions f;
  f.with_radius = false;
  const std::string no_radius = write(makeY(f), "no_radius", "binary");
  expectRefused(no_radius, "its point arrays: Abscissas");

  auto broken = [&](const std::string& name, const std::function<void(vtkPolyData*)>& damage) {
    auto data = makeY(FileOptions{});
    damage(data);
    return write(data, name, "binary");
  };
  const std::string nan_radius = broken("nan_radius", [](vtkPolyData* d) {
    d->GetPointData()->GetArray("MaximumInscribedSphereRadius")->SetTuple1(5, NAN);
  });
  expectRefused(nan_radius, "radius of point 5");
  const std::string negative = broken("negative", [](vtkPolyData* d) {
    d->GetPointData()->GetArray("MaximumInscribedSphereRadius")->SetTuple1(9, -1.0);
  });
  expectRefused(negative, "radii must be positive");
  const std::string nan_point =
      broken("nan_point", [](vtkPolyData* d) { d->GetPoints()->SetPoint(3, NAN, 0.0, 0.0); });
  expectRefused(nan_point, "point 3 is not finite");
  const std::string no_lines =
      broken("no_lines", [](vtkPolyData* d) { d->SetLines(vtkSmartPointer<vtkCellArray>::New()); });
  expectRefused(no_lines, "no lines");

  // A loop: a triangle of 2-point lines.
  auto loop = vtkSmartPointer<vtkPolyData>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto radius = vtkSmartPointer<vtkDoubleArray>::New();
  radius->SetName("MaximumInscribedSphereRadius");
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (int k = 0; k < 3; ++k) {
    points->InsertNextPoint(10.0 * std::cos(2 * M_PI * k / 3), 10.0 * std::sin(2 * M_PI * k / 3),
                            0.0);
    radius->InsertNextValue(1.0);
  }
  for (int k = 0; k < 3; ++k) {
    const vtkIdType pair[2] = {k, (k + 1) % 3};
    cells->InsertNextCell(2, pair);
  }
  loop->SetPoints(points);
  loop->SetLines(cells);
  loop->GetPointData()->AddArray(radius);
  expectRefused(write(loop, "loop", "binary"), "loop");

  // Another dataset type, an empty file, text that is not VTK.
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(2, 2, 2);
  const std::string image_path = tempFile("image.vtp");
  auto iw = vtkSmartPointer<vtkXMLImageDataWriter>::New();
  iw->SetFileName(image_path.c_str());
  iw->SetInputData(image);
  ASSERT_EQ(iw->Write(), 1);
  expectRefused(image_path, "of type ImageData, not PolyData");
  const std::string empty = tempFile("empty.vtp");
  std::ofstream(empty).close();
  expectRefused(empty, "empty");
  const std::string text = tempFile("text.vtk");
  std::ofstream(text) << "id type x y z radius parent\n1 1 0 0 0 1 -1\n";
  expectRefused(text, "not a legacy VTK file");
  for (const std::string& p : {no_radius, nan_radius, negative, nan_point, no_lines, image_path,
                               empty, text, tempFile("loop.vtp")})
    fs::remove(p);
}

}  // namespace
}  // namespace evsim
