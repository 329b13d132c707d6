// A step's statistics: its stages are consecutive on one clock, so their
// times and the remainder add up to the step's wall time, which a second
// clock around the call bounds; the parts of detection stay within it.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

struct Totals {
  double wall_ms{0.0}, outside_ms{0.0}, curvature_ms{0.0}, vessel_motion_ms{0.0};
  double device_contact_ms{0.0}, other_ms{0.0};
  int with_contacts{0}, halved{0};
};

/// Steps `scene` `steps` times, checking every step's stage sum.
Totals stepAndCheck(const std::string& scene, int steps) {
  const SceneModel model = loadScene(scene);
  SimData data = makeData(model);
  Totals t;
  for (int i = 0; i < steps; ++i) {
    const auto before = std::chrono::steady_clock::now();
    const StepStatus status = step(model, &data);
    const double outside =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - before)
            .count();
    EXPECT_EQ(status, StepStatus::kOk) << scene << " step " << i;
    const StepStats& s = data.stats;
    // The same clock's ticks summed in doubles: equal to rounding.
    EXPECT_NEAR(s.stagesMs(), s.wall_ms, 1e-9 * s.wall_ms + 1e-9) << scene << " step " << i;
    EXPECT_LE(s.wall_ms, outside) << scene << " step " << i;
    EXPECT_GE(s.other_ms, 0.0);
    const ContactTimes& c = s.contact.times;
    EXPECT_LE(c.device_contact_ms + c.coaxial_ms, c.detection_ms + 1e-9) << scene << " step " << i;
    t.wall_ms += s.wall_ms;
    t.outside_ms += outside;
    t.curvature_ms += c.curvature_ms;
    t.vessel_motion_ms += s.vessel_motion_ms;
    t.device_contact_ms += c.device_contact_ms;
    t.other_ms += s.other_ms;
    t.with_contacts += s.contact.contacts > 0 ? 1 : 0;
    t.halved += s.subdivisions > 0 ? 1 : 0;
  }
  return t;
}

TEST(StepStats, TheStagesAndTheRemainderAddUpToTheStepsWallTime) {
  // Coaxial devices against the arch's wall: the curvature term is formed.
  const Totals arch = stepAndCheck("arch_navigation", 300);
  ASSERT_GT(arch.with_contacts, 0);
  EXPECT_GT(arch.curvature_ms, 0.0);
  EXPECT_GT(arch.other_ms, 0.0);
  // A coil touching itself, halved steps; a moving vessel network.
  const Totals coil = stepAndCheck("aneurysm", 300);
  EXPECT_GT(coil.device_contact_ms, 0.0);
  const Totals moving = stepAndCheck("network", 100);
  EXPECT_GT(moving.vessel_motion_ms, 0.0);
}

}  // namespace
}  // namespace evsim
