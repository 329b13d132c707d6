// Coil detachment (a device with a detach_section): refused while the
// junction is inside the microcatheter; afterwards the withdrawn pusher
// separates from the coil, which is left free.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

/// Mean position of the nodes beyond element `cut` (the coil) [m].
Vec3 coilCentroid(const DeviceState& x, int cut) {
  Vec3 c = Vec3::Zero();
  const int n = static_cast<int>(x.position.size());
  for (int i = cut + 1; i < n; ++i) c += x.position[i];
  return c / (n - cut - 1);
}

TEST(Detach, RefusedInsideTheMicrocatheterThenThePusherLeavesTheCoil) {
  const SceneModel model = loadScene("aneurysm_coiling");
  SimData data = makeData(model);
  const int coil = findDevice(model, "finishing_coil");
  ASSERT_GE(coil, 0);
  const int cut = model.devices[coil].detach_element;
  ASSERT_EQ(cut, 24);  // the pusher's 25th element joins it to the coil

  // At 1.0 s the junction is still inside the microcatheter: refused, state kept.
  while (data.time < 1.0 - 1e-9) ASSERT_EQ(step(model, &data), StepStatus::kOk) << data.last_error;
  const std::string why = detachDevice(model, &data, "finishing_coil");
  EXPECT_NE(why.find("still in the microcatheter"), std::string::npos) << why;
  EXPECT_EQ(data.devices[coil].cut_element, -1);
  EXPECT_NE(detachDevice(model, &data, "microcatheter").find("no detach_section"),
            std::string::npos);

  // The script detaches at 1.65 s and withdraws the pusher by 5 mm from 1.7 s.
  Vec3 coil_at_detach = Vec3::Zero(), pusher_at_detach = Vec3::Zero();
  while (data.time < 2.3 - 1e-9) {
    ASSERT_EQ(step(model, &data), StepStatus::kOk)
        << "t = " << data.time << ": " << data.last_error;
    ASSERT_TRUE(data.notices.empty()) << data.notices.front();
    if (std::abs(data.time - 1.7) < 1e-9) {
      ASSERT_EQ(data.devices[coil].cut_element, cut);
      coil_at_detach = coilCentroid(data.devices[coil], cut);
      pusher_at_detach = data.devices[coil].position[cut];
    }
  }
  const DeviceState& x = data.devices[coil];
  const double pusher_back = (x.position[cut] - pusher_at_detach).norm();
  // Joined, the junction element would keep its length (2 mm, axially
  // stiff); cut, the pusher's tip leaves the coil's proximal end behind.
  const double junction_rest = model.devices[coil].elements[cut].length;
  const double junction = (x.position[cut + 1] - x.position[cut]).norm();
  EXPECT_NEAR(pusher_back, 0.005, 0.0005);                 // the commanded withdrawal
  EXPECT_GT(junction, junction_rest + 0.4 * pusher_back);  // joined: junction_rest
  const double coil_moved = (coilCentroid(x, cut) - coil_at_detach).norm();
  // The cut element stores no energy: the device's energy is its two parts'.
  DeviceState joined = x;
  joined.cut_element = -1;
  EXPECT_LT(elasticEnergy(model.devices[coil], x), elasticEnergy(model.devices[coil], joined));
  std::printf(
      "[ metric   ] pusher withdrawn %.3f mm; junction %.3f mm (rest %.3f mm); coil centroid "
      "moved %.3f mm\n",
      pusher_back * 1e3, junction * 1e3, junction_rest * 1e3, coil_moved * 1e3);
}

// The scene is a hard case: from 0.7 s the coil whips its loops round the
// dome (tip jumps of 1-8 mm in a step) and at 1.35-1.6 s the stiff pusher
// straightens the microcatheter's tip. With 20 loops and 4 halvings a 1 %
// change of the insertion speed (or of the round-off) left a step unsolved;
// the scene asks for 30 and 10. Pushed 2 % slower and faster, every step
// must still be solved.
TEST(Detach, CoilingSurvivesSmallChangesOfTheInsertionSpeed) {
  for (double factor : {0.98, 1.02}) {
    SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm_coiling"));
    ASSERT_GT(spec.script[0].command.insertion, 0.0);
    spec.script[0].command.insertion *= factor;
    const SceneModel model = buildSceneModel(spec);
    SimData data = makeData(model);
    int subdivided = 0;
    while (data.time < 1.7 - 1e-9) {
      ASSERT_EQ(step(model, &data), StepStatus::kOk)
          << "speed x" << factor << ", t = " << data.time << ": " << data.last_error;
      subdivided += data.stats.subdivisions > 0;
    }
    std::printf("[ metric   ] insertion speed x%.2f: 1,700 steps solved, %d subdivided\n", factor,
                subdivided);
  }
}

}  // namespace
}  // namespace evsim
