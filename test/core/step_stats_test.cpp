// A step's statistics: the stage times it reports are disjoint (each stage
// counted once), so their sum never exceeds the step's wall time, and the
// wall's curvature term is timed as a stage of its own.
#include <gtest/gtest.h>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

/// The disjoint stages of a step [ms] (device_contact_ms and coaxial_ms are
/// parts of detection_ms and not added again).
double stageSum(const StepStats& s) {
  return s.assembly_ms + s.factorization_ms + s.solve_ms + s.detection_ms + s.delassus_ms +
         s.lcp_ms + s.correction_ms + s.curvature_ms + s.vessel_motion_ms;
}

TEST(StepStats, TheDisjointStagesAddUpToAtMostTheStepsWallTime) {
  const SceneModel model = loadScene("arch_navigation");
  SimData data = makeData(model);
  double curvature_ms = 0.0, stages_ms = 0.0, wall_ms = 0.0;
  int with_contacts = 0;
  for (int i = 0; i < 300; ++i) {
    ASSERT_EQ(step(model, &data), StepStatus::kOk);
    const StepStats& s = data.stats;
    // each stage is timed inside the step's own timer; 1 us of slack for
    // the clocks' rounding
    EXPECT_LE(stageSum(s), s.wall_ms + 1e-3) << "step " << data.step;
    EXPECT_LE(s.device_contact_ms + s.coaxial_ms, s.detection_ms + 1e-3);
    with_contacts += s.contacts > 0 ? 1 : 0;
    curvature_ms += s.curvature_ms;
    stages_ms += stageSum(s);
    wall_ms += s.wall_ms;
  }
  ASSERT_GT(with_contacts, 0);  // the wire reaches the wall: the curvature term is formed
  EXPECT_GT(curvature_ms, 0.0);
  EXPECT_LE(stages_ms, wall_ms);
}

}  // namespace
}  // namespace evsim
