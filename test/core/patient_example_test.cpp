// The shipped patient example (config/vessels/example_patient.vtp, written
// by VTK's Python writer in scripts/make_patient_centerline.py from the arch
// of carotid.swc, as a segmentation would give it: one noisy polyline per
// outlet) against the SWC it was made from: the merged and simplified tree
// has the same branches, of the same lengths and radii, and its surface
// keeps the radii.
#include <gtest/gtest.h>

#include <cstdio>

#include "endovascular_sim/geometry/surface_fidelity.h"
#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/geometry/vessel_field.h"
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

}  // namespace
}  // namespace evsim
