// The shipped patient example (config/vessels/example_patient.vtp, written
// by VTK's Python writer in scripts/make_patient_centerline.py from the arch
// of carotid.swc, as a segmentation would give it: one noisy polyline per
// outlet) against the SWC it was made from: the merged and simplified tree
// has the same branches, of the same lengths and radii, and its surface
// keeps the radii.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/surface_fidelity.h"
#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "endovascular_sim/scene/centerline_scene.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

TEST(PatientExample, TheMergedTreeIsTheArchItWasMadeFrom) {
  const SceneModel patient = loadScene("patient_example");
  const SceneModel arch = loadScene("carotid");
  const VesselAtlas& p = *patient.atlas;
  const VesselAtlas& a = *arch.atlas;
  for (const char* name :
       {"brachiocephalic_trunk", "right_subclavian", "right_common_carotid",
        "right_internal_carotid", "right_external_carotid", "left_common_carotid",
        "left_internal_carotid", "left_external_carotid", "left_subclavian"}) {
    SCOPED_TRACE(name);
    ASSERT_GE(p.find(name), 0);
    const NamedVessel& vp = p.vessels()[p.find(name)];
    const NamedVessel& va = a.vessels()[a.find(name)];
    EXPECT_NEAR(vp.length, va.length, 1e-3);              // the fork within a millimetre
    EXPECT_NEAR(vp.radius, va.radius, 0.05 * va.radius);  // 5 % noise, smoothed
    EXPECT_EQ(p.vessels()[vp.parent].name == "aortic_arch" ||
                  p.vessels()[vp.parent].name == "distal_aortic_arch" ||
                  p.vessels()[vp.parent].name == "descending_aorta",
              a.vessels()[va.parent].name == "aortic_arch");
  }
  // The aorta, cut at other forks: the same length in all.
  double aorta_p = 0.0, aorta_a = 0.0;
  for (const char* name :
       {"ascending_aorta", "aortic_arch", "distal_aortic_arch", "descending_aorta"}) {
    if (p.find(name) >= 0) aorta_p += p.vessels()[p.find(name)].length;
    if (a.find(name) >= 0) aorta_a += a.vessels()[a.find(name)].length;
  }
  EXPECT_NEAR(aorta_p, aorta_a, 1e-3);
}

/// The arch a segmentation splits at each ostium (branches 8 and 10), named
/// as one vessel: its length the two branches', the left common carotid
/// branching off it part way along; branches that are no chain refused.
TEST(PatientExample, ConsecutiveBranchesNameOneVessel) {
  SceneSpec spec = loadSceneFile(resolveScenePath("patient_example"));
  ASSERT_EQ(spec.vessels.tree.names.at(8), "aortic_arch");
  ASSERT_EQ(spec.vessels.tree.names.at(10), "aortic_arch");
  const VesselAtlas chain(buildCenterline(spec.vessels));
  spec.vessels.tree.names[8] = "distal_aortic_arch";
  const VesselAtlas split(buildCenterline(spec.vessels));
  const NamedVessel& arch = chain.vessels()[chain.find("aortic_arch")];
  const double parts = split.vessels()[split.find("aortic_arch")].length +
                       split.vessels()[split.find("distal_aortic_arch")].length;
  EXPECT_NEAR(arch.length, parts, 1e-9);
  const NamedVessel& lcca = chain.vessels()[chain.find("left_common_carotid")];
  EXPECT_EQ(chain.vessels()[lcca.parent].name, "aortic_arch");
  EXPECT_GT(lcca.origin_depth, 0.01);  // off the chain's side, not at an end
  EXPECT_LT(lcca.origin_depth, arch.length - 0.01);
  EXPECT_EQ(chain.find("distal_aortic_arch"), -1);
  EXPECT_EQ(chain.vessels().size() + 1, split.vessels().size());
  // Siblings (the left subclavian, 6, and the arch's first part, 8) are no chain.
  spec.vessels.tree.names[6] = "distal_aortic_arch";
  try {
    buildCenterline(spec.vessels);
    ADD_FAILURE() << "two sibling branches named as one vessel";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("do not follow one another"), std::string::npos)
        << e.what();
  }
}

TEST(PatientExample, ItsSurfaceKeepsTheRadiiOfTheFile) {
  const SceneSpec spec = loadSceneFile(resolveScenePath("patient_example"));
  const Centerline c = buildCenterline(spec.vessels);
  const SurfaceFidelity f = measureSurfaceFidelity(VesselField(c, {}, {}, spec.vessels.field), c);
  std::printf(
      "[ metric   ] patient example: lumen radius against the tree's, along the vessels "
      "median %.2f %% worst %.2f %% (%d rays); at forks and ends median %.2f %% (%d rays)\n",
      100 * f.along.median, 100 * f.along.worst, f.along.rays, 100 * f.at_forks.median,
      f.at_forks.rays);
  EXPECT_GT(f.along.rays, 200);
  EXPECT_LT(f.along.median, 0.05);
  EXPECT_LT(f.along.worst, 0.15);
}

/// The shipped centreline file alone, in a scene of patient_example's
/// devices (what the node's load_centerline builds).
SceneSpec bareCentrelineScene(const std::string& units) {
  const SceneSpec base = loadSceneFile(resolveScenePath("patient_example"));
  CenterlineSceneRequest request;
  request.centerline = configDirectory() + "/vessels/example_patient.vtp";
  request.units = units;
  request.frame = "LAS";  // the base lies supine: the file's frame says where posterior is
  return centerlineScene(base, request);
}

TEST(PatientExample, TheBareCentrelineLoadsAsASceneEnteredAtItsWidestEnd) {
  const SceneSpec spec = bareCentrelineScene("mm");
  EXPECT_EQ(spec.name, "example_patient");
  EXPECT_TRUE(spec.targets.empty());
  ASSERT_EQ(spec.script.size(), 1u) << "the base's script: in at 30 mm/s";
  const SceneModel m = buildSceneModel(spec);
  ASSERT_EQ(m.devices.size(), 1u);
  EXPECT_EQ(m.devices[0].name, "guidewire");
  // The inlet: the widest end of the tree (no inlet declared), the wire one
  // radius in along the first branch.
  const Centerline& c = *m.centerline;
  std::vector<int> children(c.numPoints(), 0);
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.parent[i] >= 0) ++children[c.parent[i]];
  int root = -1;
  double widest_end = 0.0;
  for (int i = 0; i < c.numPoints(); ++i) {
    if (c.parent[i] < 0) root = i;
    if (children[i] == 0 || c.parent[i] < 0) widest_end = std::max(widest_end, c.radius[i]);
  }
  ASSERT_GE(root, 0);
  EXPECT_DOUBLE_EQ(c.radius[root], widest_end);
  EXPECT_NEAR((m.introducers[0].access_point - c.position[root]).norm(), c.radius[root], 1e-6);
  // Every branch is named by its id; the wire goes in without a failed step.
  for (const NamedVessel& v : m.atlas->vessels()) EXPECT_EQ(v.name.rfind("branch_", 0), 0u);
  SimData d = makeData(m);
  for (int k = 0; k < 1500; ++k) ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
  EXPECT_NEAR(d.devices[0].inserted_length, 0.02 + 0.045, 1e-6);
  EXPECT_TRUE(m.atlas->locate(d.devices[0].position.back()).inside) << "the tip in the tree";
}

TEST(PatientExample, ABareCentrelineWithoutUnitsIsRefused) {
  for (const auto& [units, words] :
       {std::pair{std::string(""), std::string("units declared")},
        std::pair{std::string("inch"), std::string("must be m, cm, mm or um")}}) {
    try {
      bareCentrelineScene(units);
      ADD_FAILURE() << "units '" << units << "' accepted";
    } catch (const LoadError& e) {
      EXPECT_EQ(e.field(), "units");
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(e.file().find("example_patient.vtp"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace evsim
