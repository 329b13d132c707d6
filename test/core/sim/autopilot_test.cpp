// The navigation autopilot: from the femoral access, a guidewire in a
// shaped catheter reaches each vessel of the arch (a scene per target). That the tip is in the
// target is judged against the SWC centreline itself (distance to the
// vessel's polyline below its radius, 20 mm of path past its origin), not
// the atlas the autopilot steers by.
#include "endovascular_sim/sim/autopilot.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/centerline.h"
#include "lumen_check.h"

namespace evsim {
namespace {

struct OnCenterline {
  double distance{std::numeric_limits<double>::infinity()};  // [m] to the vessel's polyline
  double radius{0.0};                                        // [m] there
  double depth{0.0};  // [m] path length from the vessel's first segment's start
};

/// Nearest point of a named vessel's SWC polyline (its points in file order).
OnCenterline nearestOn(const Centerline& c, const std::string& name, const Vec3& p) {
  int v = -1;
  for (size_t k = 0; k < c.vessel_names.size(); ++k)
    if (c.vessel_names[k] == name) v = static_cast<int>(k);
  OnCenterline best;
  double s = 0.0;
  for (int i = 0; i < c.numPoints(); ++i) {
    if (c.vessel[i] != v) continue;
    const Vec3 a = c.position[c.parent[i]], b = c.position[i];
    const double len = (b - a).norm();
    const double t = std::clamp((p - a).dot(b - a) / (len * len), 0.0, 1.0);
    const double d = (p - a - t * (b - a)).norm();
    if (d < best.distance) best = {d, c.radius[i], s + t * len};
    s += len;
  }
  return best;
}

struct Case {
  const char* scene;
  const char* target;
};

class ArchNavigation : public ::testing::TestWithParam<Case> {};

/// Runs the autopilot to `target` for at most `limit` [s] of simulated time,
/// as evsim navigate and the node do (the recovery options once).
void navigate(const SceneModel& model, SimData* data, Autopilot* pilot, double limit) {
  while (!pilot->done() && data->time < limit) {
    pilot->control(model, data);
    bool recovered = false;
    const StepStatus status = stepOrRecover(model, data, &recovered);
    pilot->observe(*data, status != StepStatus::kOk);
    ASSERT_EQ(status, StepStatus::kOk) << data->last_error;
    // Every point of the wire in the catheter's lumen, checked point by
    // point (the loop plans one plane per element and side).
    ASSERT_LE(test::worstLumenExcess(model, *data), 2.0 * model.contact.lumen_tolerance)
        << "t = " << data->time;
  }
}

TEST_P(ArchNavigation, TheAutopilotReachesTheVesselWithoutAFailedStep) {
  const char* target = GetParam().target;
  const SceneModel model = loadScene(GetParam().scene);
  SimData data = makeData(model);
  Autopilot pilot(model, data, target);
  ASSERT_EQ(model.devices[pilot.device()].name, "guidewire");
  navigate(model, &data, &pilot, 30.0);
  const AutopilotReport& r = pilot.report();
  ASSERT_TRUE(r.reached) << r.reason;
  EXPECT_EQ(r.failed_steps, 0);
  EXPECT_LT(r.time, 15.0);
  // The scene's own target tracker saw it too.
  bool tracked = false;
  for (size_t k = 0; k < model.targets.size(); ++k)
    if (model.targets[k].spec.vessel == target) tracked = data.targets[k].reached;
  EXPECT_TRUE(tracked);
  // Independent: the wire's tip in the vessel's lumen, 20 mm along it.
  const Centerline c = loadCenterlineFile(configDirectory() + "/vessels/carotid.swc");
  const OnCenterline on = nearestOn(c, target, data.devices[pilot.device()].position.back());
  EXPECT_LT(on.distance, on.radius) << target;
  EXPECT_GT(on.depth, 0.015) << target;  // the polyline starts one point past the junction
}

// One procedure scene per target: the angled catheter for the left-side
// branches, the Headhunter curve for the brachiocephalic trunk's.
INSTANTIATE_TEST_SUITE_P(
    Targets, ArchNavigation,
    ::testing::Values(Case{"arch_to_left_common_carotid", "left_common_carotid"},
                      Case{"arch_to_left_subclavian", "left_subclavian"},
                      Case{"arch_to_right_common_carotid", "right_common_carotid"},
                      Case{"arch_to_right_subclavian", "right_subclavian"}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.target); });

// Deep in the generated network: the pair engages the left common and
// external carotids and the external carotid's first branch, then the
// microwire's angled tip takes that branch's first daughter (4 bifurcations
// from the access). Judged against the generated centreline's polyline of
// the target (the scene's skeleton), not the atlas the autopilot steers by.
TEST(NetworkNavigation, AMicrowireReachesABranchFourBifurcationsDeep) {
  const std::string target = "left_external_carotid_1_1";
  const SceneModel model = loadScene("network_navigation");
  SimData data = makeData(model);
  Autopilot pilot(model, data, target);
  ASSERT_EQ(model.devices[pilot.device()].name, "microwire");
  navigate(model, &data, &pilot, 40.0);
  const AutopilotReport& r = pilot.report();
  std::printf("[ metric   ] %s reached at %.3f s, %d retries, peak wall force %.2f N\n",
              target.c_str(), r.time, r.retries, r.peak_wall_force);
  ASSERT_TRUE(r.reached) << r.reason;
  EXPECT_EQ(r.failed_steps, 0);
  const OnCenterline on =
      nearestOn(*model.centerline, target, data.devices[pilot.device()].position.back());
  EXPECT_LT(on.distance, on.radius) << target;
  const NamedVessel& v = model.atlas->vessels()[model.atlas->find(target)];
  EXPECT_GT(on.depth, 0.5 * requiredDepth(v, 0.02)) << target;  // (the polyline starts past the
                                                                // junction: half, not all of it)
}

LoadError refusal(const std::string& scene, const std::string& target,
                  const std::string& device = "") {
  const SceneModel model = loadScene(scene);
  const SimData data = makeData(model);
  try {
    Autopilot pilot(model, data, target, device);
  } catch (const LoadError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted " << target;
  return LoadError("", 0, "", "");
}

TEST(Autopilot, RefusesWhatCannotBeNavigatedAndNamesWhatExists) {
  const std::string typo = refusal("arch_navigation", "left_comon_carotid").what();
  EXPECT_NE(typo.find("no vessel 'left_comon_carotid'"), std::string::npos) << typo;
  EXPECT_NE(typo.find("nearest: left_common_carotid"), std::string::npos) << typo;
  const std::string device = refusal("arch_navigation", "left_subclavian", "microwire").what();
  EXPECT_NE(device.find("no device 'microwire'"), std::string::npos) << device;
  const std::string free = refusal("free_insertion", "left_subclavian").what();
  EXPECT_NE(free.find("has no vessels"), std::string::npos) << free;
}

}  // namespace
}  // namespace evsim
