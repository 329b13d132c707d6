// Effects: a scene simulates only the effects it names. An effect that is off
// is never entered (its counter stays at zero) and nothing is built for it;
// one that is on is entered.
#include <gtest/gtest.h>

#include <algorithm>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

bool named(const SceneSpec& spec, const std::string& effect) {
  return std::find(spec.effects.begin(), spec.effects.end(), effect) != spec.effects.end();
}

SceneSpec withEffects(SceneSpec spec, const std::vector<std::string>& effects) {
  spec.effects = effects;
  return spec;
}

EffectCounters run(const SceneSpec& spec, long steps, StepStatus* last = nullptr) {
  const SceneModel model = buildSceneModel(spec);
  SimData data = makeData(model);
  StepStatus status = StepStatus::kOk;
  for (long k = 0; k < steps && status == StepStatus::kOk; ++k) status = step(model, &data);
  if (last) *last = status;
  return data.effect_calls;
}

TEST(Effects, ShippedScenesEnterOnlyTheEffectsTheyName) {
  for (const std::string& name : shippedScenes()) {
    const SceneSpec spec = loadSceneFile(resolveScenePath(name));
    const EffectCounters c = run(spec, 300);
    EXPECT_EQ(c.gravity > 0, named(spec, "gravity")) << name;
    EXPECT_EQ(c.vessel_motion > 0, named(spec, "vessel_motion")) << name;
    EXPECT_EQ(c.device_contact > 0, named(spec, "device_contact")) << name;
    EXPECT_EQ(c.blood_drag > 0, named(spec, "blood_drag")) << name;
    if (!named(spec, "subdivision")) {
      EXPECT_EQ(c.subdivision, 0) << name;
    }
  }
}

TEST(Effects, GravityOffIsNeverApplied) {
  const SceneSpec spec = loadSceneFile(resolveScenePath("free_insertion"));
  EXPECT_GT(run(spec, 50).gravity, 0);
  EXPECT_EQ(run(withEffects(spec, {}), 50).gravity, 0);
  const SceneModel model = buildSceneModel(withEffects(spec, {}));
  EXPECT_EQ(model.gravity, Vec3::Zero());
}

TEST(Effects, BloodDragOnlyWhenNamed) {
  const SceneSpec spec = loadSceneFile(resolveScenePath("free_insertion"));
  ASSERT_FALSE(named(spec, "blood_drag"));
  EXPECT_EQ(run(spec, 50).blood_drag, 0);
  EXPECT_TRUE(buildSceneModel(spec).devices[0].node_drag_across.empty());  // nothing built
  const SceneSpec in_blood = withEffects(spec, {"gravity", "blood_drag"});
  EXPECT_GT(run(in_blood, 50).blood_drag, 0);
  EXPECT_FALSE(buildSceneModel(in_blood).devices[0].node_drag_across.empty());
}

TEST(Effects, VesselMotionOffBuildsNoMotion) {
  const SceneSpec spec = loadSceneFile(resolveScenePath("network"));
  ASSERT_TRUE(named(spec, "vessel_motion"));
  EXPECT_TRUE(buildSceneModel(spec).vessels->moves());
  const SceneSpec still = withEffects(spec, {"gravity", "subdivision"});
  EXPECT_FALSE(buildSceneModel(still).vessels->moves());  // no regions stored
  EXPECT_EQ(run(still, 100).vessel_motion, 0);
}

TEST(Effects, DeviceContactOnlyWhenNamed) {
  const SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm"));
  ASSERT_TRUE(named(spec, "device_contact"));
  EXPECT_GT(run(spec, 200).device_contact, 0);
  EXPECT_EQ(run(withEffects(spec, {"gravity", "subdivision"}), 200).device_contact, 0);
}

TEST(Effects, SubdivisionHalvesOnlyWhenNamed) {
  // One activation loop cannot solve the coil's contacts: with the effect the
  // steps are halved and go on; without it a step is rejected, never halved.
  SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm"));
  spec.contact.max_activation_loops = 1;
  StepStatus with_status, without_status;
  const EffectCounters with = run(spec, 600, &with_status);
  EXPECT_GT(with.subdivision, 0);
  const EffectCounters without =
      run(withEffects(spec, {"gravity", "device_contact"}), 600, &without_status);
  EXPECT_EQ(without.subdivision, 0);
  EXPECT_EQ(without_status, StepStatus::kContactsUnsolved);
}

}  // namespace
}  // namespace evsim
