// Helpers of the tests of patient centrelines read from VTK files: the
// known Y (a 60 mm trunk of 6 mm radius splitting into branches of 3 and
// 2.5 mm), sampling it, writing a PolyData with VTK in a data mode, loading
// it, and checking a tree against the Y.
#pragma once

#include <gtest/gtest.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "endovascular_sim/scene/centerline_vtk.h"

namespace evsim {
namespace vtk_y {

namespace fs = std::filesystem;

/// The known Y [mm]: trunk (0,0,0) -> (0,0,60), then to the left outlet
/// (-20,0,100) and the right outlet (20,0,100).
inline const Vec3 kInlet(0, 0, 0), kFork(0, 0, 60), kLeft(-20, 0, 100), kRight(20, 0, 100);
constexpr double kTrunkR = 6.0, kLeftR = 3.0, kRightR = 2.5;

struct Sampled {
  std::vector<Vec3> x;  // [mm]
  std::vector<double> r;
};

/// a -> b every `step` mm (a included, b included), radius ra -> rb.
inline void sample(const Vec3& a, const Vec3& b, double ra, double rb, double step, bool from_a,
                   Sampled* out) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
  for (int k = from_a ? 0 : 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    out->x.push_back(a + t * (b - a));
    out->r.push_back(ra + t * (rb - ra));
  }
}

inline std::string tempFile(const std::string& name) {
  return (fs::temp_directory_path() / ("evsim_vtk_test_" + name)).string();
}

inline std::string write(vtkPolyData* data, const std::string& name, const std::string& mode) {
  if (mode == "legacy") {
    const std::string path = tempFile(name + ".vtk");
    auto w = vtkSmartPointer<vtkPolyDataWriter>::New();
    w->SetFileName(path.c_str());
    w->SetInputData(data);
    w->SetFileTypeToBinary();
    EXPECT_EQ(w->Write(), 1);
    return path;
  }
  const std::string path = tempFile(name + ".vtp");
  auto w = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
  w->SetFileName(path.c_str());
  w->SetInputData(data);
  if (mode == "ascii") {
    w->SetDataModeToAscii();
  } else if (mode == "binary") {
    w->SetDataModeToBinary();  // base64, zlib-compressed
    w->SetCompressorTypeToZLib();
  } else if (mode == "appended") {
    w->SetDataModeToAppended();  // base64
    w->SetCompressorTypeToZLib();
  } else {  // raw appended bytes, uncompressed
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();
    w->SetCompressorTypeToNone();
  }
  EXPECT_EQ(w->Write(), 1);
  return path;
}

inline Centerline load(const std::string& path, double unit, CenterlineTreeReport* report,
                       const CenterlineTreeOptions& tree = {}) {
  VtkCenterlineOptions o;
  o.unit = unit;
  o.tree = tree;
  return loadVtkCenterline(path, o, report);
}

/// The tree's point nearest p [m] and its distance.
inline int nearest(const Centerline& c, const Vec3& p, double* d) {
  int best = -1;
  *d = 1e9;
  for (int i = 0; i < c.numPoints(); ++i)
    if ((c.position[i] - p).norm() < *d) *d = (c.position[i] - p).norm(), best = i;
  return best;
}

/// The Y's shape: three vessels, the fork and the outlets where they are,
/// and the radii of each branch.
inline void expectTheY(const Centerline& c, const CenterlineTreeReport& report,
                       const std::string& what, int max_points = 20) {
  SCOPED_TRACE(what);
  ASSERT_EQ(c.vessel_names.size(), 3u);
  EXPECT_EQ(report.branches, 3);
  double d;
  std::vector<int> children(c.numPoints(), 0);
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.parent[i] >= 0) ++children[c.parent[i]];
  ASSERT_EQ(std::count(children.begin(), children.end(), 2), 1) << "one fork";
  const int fork =
      static_cast<int>(std::find(children.begin(), children.end(), 2) - children.begin());
  EXPECT_LT((c.position[fork] - 1e-3 * kFork).norm(), 0.35e-3) << "the fork";
  for (const auto& [outlet, r] : {std::pair{kLeft, kLeftR}, std::pair{kRight, kRightR}}) {
    const int o = nearest(c, 1e-3 * outlet, &d);
    EXPECT_LT(d, 1e-6) << "an outlet";
    EXPECT_NEAR(c.radius[o], 1e-3 * r, 0.03e-3);
  }
  const int inlet = nearest(c, 1e-3 * kInlet, &d);
  EXPECT_LT(d, 0.02e-3);
  EXPECT_EQ(c.parent[inlet], -1);
  EXPECT_NEAR(c.radius[inlet], 1e-3 * kTrunkR, 0.03e-3);
  EXPECT_LT(c.numPoints(), max_points) << "straight branches simplify to a few points";
  EXPECT_LE(report.max_axis_error, CenterlineTreeOptions{}.tolerance);
}

}  // namespace vtk_y
}  // namespace evsim
