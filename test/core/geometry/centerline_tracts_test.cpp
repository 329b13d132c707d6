// The output of `vmtkbranchextractor`, written here by VTK: the known Y's
// two centrelines (to the left and the right outlet), each cut into tracts
// as VMTK cuts them (its own points per tract, the split point written by
// both tracts, cell arrays CenterlineIds, TractIds, GroupIds, Blanking; the
// trunk group 0, the bifurcation's blanked group 1, the branches 2 and 3),
// the cells in shuffled order. The tree must be the Y with the groups as
// branch ids, even where the two centrelines' trunks run apart by a third
// of its radius (geometry alone would cut the trunk in two there).
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/vessel_atlas.h"
#include "vtk_centerline_fixture.h"

namespace evsim {
namespace {

using namespace vtk_y;  // NOLINT: the Y's helpers

/// A tract: its points [mm] and radii, its cell data.
struct Tract {
  Sampled x;
  int centerline, tract, group, blanked;
};

struct TractOptions {
  double trunk_bump{0.0};  // [mm] the right centreline's trunk bowed sideways by this much
  bool groups{true};       // GroupIds and Blanking written
  double tract_gap{0.0};   // [mm] the right branch's tract starts this far from the split point
  bool duplicate_tract{false};
};

/// The Y's centrelines cut where VMTK cuts them: 6 mm before the fork
/// (trunk | bifurcation) and 6 mm after it along each branch (bifurcation |
/// branch); the bifurcation's tracts blanked.
std::vector<Tract> tractsOfY(const TractOptions& o) {
  const Vec3 cut_in = kFork - Vec3(0, 0, 6);
  std::vector<Tract> out;
  for (int c = 0; c < 2; ++c) {
    const Vec3 outlet = c == 0 ? kLeft : kRight;
    const double r = c == 0 ? kLeftR : kRightR;
    const Vec3 cut_out = kFork + 6.0 * (outlet - kFork).normalized();
    Tract trunk{{}, c, 0, 0, 0}, fork{{}, c, 1, 1, 1}, branch{{}, c, 2, 2 + c, 0};
    sample(kInlet, cut_in, kTrunkR, kTrunkR, 0.3, true, &trunk.x);
    if (c == 1)  // the second centreline bowed off the first along the trunk's middle
      for (Vec3& p : trunk.x.x)
        if (p.z() > 10.0 && p.z() < 44.0)
          p.x() += o.trunk_bump * std::sin(M_PI * (p.z() - 10.0) / 34.0);
    sample(cut_in, kFork, kTrunkR, kTrunkR, 0.3, true, &fork.x);
    sample(kFork, cut_out, kTrunkR, r, 0.3, false, &fork.x);
    sample(cut_out, outlet, r, r, 0.3, true, &branch.x);
    if (c == 1) branch.x.x.front().y() += o.tract_gap;
    out.insert(out.end(), {trunk, fork, branch});
  }
  if (o.duplicate_tract) out.push_back(out[1]);
  return out;
}

std::string writeTracts(const std::vector<Tract>& tracts, const TractOptions& o,
                        const std::string& name) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto radius = vtkSmartPointer<vtkDoubleArray>::New();
  radius->SetName("MaximumInscribedSphereRadius");
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  std::vector<vtkSmartPointer<vtkIntArray>> arrays;
  for (const char* array : {"CenterlineIds", "TractIds", "GroupIds", "Blanking"}) {
    arrays.push_back(vtkSmartPointer<vtkIntArray>::New());
    arrays.back()->SetName(array);
  }
  // Shuffled: the last centreline's last tract first, and so on.
  for (size_t i = tracts.size(); i-- > 0;) {
    const Tract& t = tracts[i];
    std::vector<vtkIdType> ids;
    for (size_t k = 0; k < t.x.x.size(); ++k) {
      ids.push_back(points->InsertNextPoint(t.x.x[k].x(), t.x.x[k].y(), t.x.x[k].z()));
      radius->InsertNextValue(t.x.r[k]);
    }
    cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    const int values[4] = {t.centerline, t.tract, t.group, t.blanked};
    for (int a = 0; a < 4; ++a) arrays[a]->InsertNextValue(values[a]);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetLines(cells);
  data->GetPointData()->AddArray(radius);
  for (int a = 0; a < (o.groups ? 4 : 2); ++a) data->GetCellData()->AddArray(arrays[a]);
  return write(data, name, "binary");
}

/// The tree's fork: the one point with two children.
Vec3 forkOf(const Centerline& c) {
  std::vector<int> children(c.numPoints(), 0);
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.parent[i] >= 0) ++children[c.parent[i]];
  const auto fork = std::find(children.begin(), children.end(), 2);
  return fork == children.end() ? Vec3::Constant(1e9) : c.position[fork - children.begin()];
}

TEST(CenterlineTracts, BranchExtractorOutputIsTheYWithItsGroupsAsBranchIds) {
  for (double bump : {0.0, 2.0}) {
    TractOptions o;
    o.trunk_bump = bump;
    const std::string path = writeTracts(tractsOfY(o), o, "tracts");
    CenterlineTreeReport report;
    CenterlineTreeOptions names;
    names.names = {{0, "trunk"}, {2, "left_branch"}, {3, "right_branch"}};
    const Centerline c = load(path, 1e-3, &report, names);
    const std::string what = "trunk bowed by " + std::to_string(bump) + " mm";
    expectTheY(c, report, what, bump > 0.0 ? 40 : 20);  // the bow kept, if longer
    EXPECT_TRUE(report.overlapping && report.grouped) << what;
    EXPECT_EQ(report.tracts, 6) << what;
    std::vector<int> ids = report.branch_ids;
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(ids, (std::vector<int>{0, 2, 3})) << what;
    // The fork inside the blanked bifurcation (6 mm either side of it).
    EXPECT_LT((forkOf(c) - 1e-3 * kFork).norm(), 6e-3) << what;
    const VesselAtlas atlas(c);
    EXPECT_EQ(atlas.locate(1e-3 * Vec3(0, 0, 30)).vessel, atlas.find("trunk")) << what;
    EXPECT_EQ(atlas.locate(1e-3 * Vec3(-15, 0, 90)).vessel, atlas.find("left_branch")) << what;
    EXPECT_EQ(atlas.locate(1e-3 * Vec3(15, 0, 90)).vessel, atlas.find("right_branch")) << what;
    fs::remove(path);
  }
}

TEST(CenterlineTracts, WithoutGroupsTheGeometryMergesAndCutsTheBowedTrunkInTwo) {
  // The same tracts without GroupIds and Blanking: reassembled per
  // centreline and merged by geometry alone. Straight trunks give the Y;
  // the trunk bowed by a third of its radius parts from the other where the
  // bow begins: the groups are what keeps it one vessel.
  for (double bump : {0.0, 2.0}) {
    TractOptions o;
    o.trunk_bump = bump;
    o.groups = false;
    const std::string path = writeTracts(tractsOfY(o), o, "tracts_geometry");
    CenterlineTreeReport report;
    const Centerline c = load(path, 1e-3, &report);
    EXPECT_FALSE(report.grouped);
    EXPECT_EQ(report.tracts, 6);
    if (bump == 0.0)
      expectTheY(c, report, "straight trunks, geometry");
    else
      EXPECT_GT((forkOf(c) - 1e-3 * kFork).norm(), 10e-3) << "the bowed trunk's split";
    fs::remove(path);
  }
}

TEST(CenterlineTracts, TractsThatDoNotFollowEachOtherAreRefused) {
  TractOptions gap;
  gap.tract_gap = 4.0;  // beyond the 2.5 mm radius there
  const std::string apart = writeTracts(tractsOfY(gap), gap, "tracts_apart");
  TractOptions twice;
  twice.duplicate_tract = true;
  const std::string doubled = writeTracts(tractsOfY(twice), twice, "tracts_doubled");
  for (const auto& [path, expect] : {std::pair{apart, std::string("centreline 1: tract 2 starts")},
                                     std::pair{doubled, std::string("has two tracts 1")}}) {
    CenterlineTreeReport report;
    try {
      load(path, 1e-3, &report);
      ADD_FAILURE() << path << " was accepted";
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
      EXPECT_EQ(e.file(), path);
    }
    fs::remove(path);
  }
}

}  // namespace
}  // namespace evsim
