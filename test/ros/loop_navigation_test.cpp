// The node's loop running the autopilot (what the NavigateTo action
// serves): the loop's navigation ends exactly where the same autopilot run
// headless ends (same steps, same commands), refusals name what exists, and
// a manual command pre-empts the navigation and stops the devices.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <thread>

#include "endovascular_sim/ros/simulation_loop.h"

namespace evsim {
namespace {

bool eventually(const std::function<bool()>& condition, int limit_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(limit_s);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// The same navigation headless, as `evsim navigate` runs it.
AutopilotReport headless(const SceneModel& model, const std::string& target) {
  SimData data = makeData(model);
  return runAutopilot(model, &data, target);
}

class LoopNavigation : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = std::make_shared<const SceneModel>(loadScene("arch_navigation"));
    loop_.setScene(model_, /*use_script=*/true);
  }
  std::shared_ptr<const SceneModel> model_;
  SimulationLoop loop_{100.0};
};

TEST_F(LoopNavigation, ReachesTheTargetAsTheHeadlessAutopilotDoes) {
  long id = 0;
  ASSERT_EQ(loop_.startNavigation("left_subclavian", "", {}, &id), "");
  EXPECT_EQ(id, 1);
  loop_.start();
  std::vector<std::string> events, vessels;
  ASSERT_TRUE(eventually(
      [&] {
        const NavigationStatus s = loop_.navigation();
        events.insert(events.end(), s.events.begin(), s.events.end());
        if (vessels.empty() || vessels.back() != s.vessel) vessels.push_back(s.vessel);
        return s.done;
      },
      240));
  const NavigationStatus s = loop_.navigation();
  EXPECT_FALSE(s.active);
  ASSERT_TRUE(s.report.reached) << s.report.reason;
  EXPECT_EQ(s.vessel, "left_subclavian");
  ASSERT_FALSE(events.empty());
  EXPECT_NE(events.back().find("reached left_subclavian"), std::string::npos) << events.back();
  EXPECT_EQ(vessels.front(), "descending_aorta");
  // The loop stepped the same trajectory as a headless run: same end.
  const AutopilotReport h = headless(*model_, "left_subclavian");
  EXPECT_NEAR(s.report.time, h.time, 0.5 * model_->time_step);
  EXPECT_EQ(s.report.retries, h.retries);
  EXPECT_EQ(s.report.failed_steps, 0);
  EXPECT_DOUBLE_EQ(s.report.peak_wall_force, h.peak_wall_force);
  // The drives stop once the target is reached.
  const double inserted = loop_.snapshot().devices[0].inserted_length;
  const double t = loop_.snapshot().time;
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().time > t + 0.05; }, 30));
  EXPECT_EQ(loop_.snapshot().devices[0].inserted_length, inserted);
}

TEST_F(LoopNavigation, RefusesAnUnknownTargetAndNamesTheNearest) {
  const std::string why = loop_.startNavigation("left_comon_carotid", "", {}, nullptr);
  EXPECT_NE(why.find("nearest: left_common_carotid"), std::string::npos) << why;
  EXPECT_FALSE(loop_.navigation().active);
  EXPECT_NE(loop_.startNavigation("left_subclavian", "microwire", {}, nullptr), "");
}

TEST_F(LoopNavigation, AManualCommandPreEmptsTheNavigation) {
  ASSERT_EQ(loop_.startNavigation("left_common_carotid", "", {}, nullptr), "");
  loop_.start();
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().time > 0.3; }, 60));
  ASSERT_TRUE(loop_.navigation().active);
  DriveCommand hold;  // zero speed: the clinician takes the wire
  ASSERT_EQ(loop_.setCommand("catheter", hold), "");
  const NavigationStatus s = loop_.navigation();
  EXPECT_FALSE(s.active);
  EXPECT_TRUE(s.done);
  EXPECT_FALSE(s.report.reached);
  EXPECT_NE(s.report.reason.find("manual command for 'catheter'"), std::string::npos)
      << s.report.reason;
  // Every drive stopped: nothing moves the devices in.
  const std::vector<DeviceState> before = loop_.snapshot().devices;
  const double t = loop_.snapshot().time;
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().time > t + 0.05; }, 30));
  for (size_t i = 0; i < before.size(); ++i)
    EXPECT_NEAR(loop_.snapshot().devices[i].inserted_length, before[i].inserted_length, 1e-12);
  // A reset while navigating pre-empts it too.
  long id = 0;
  ASSERT_EQ(loop_.startNavigation("left_common_carotid", "", {}, &id), "");
  EXPECT_EQ(id, 2);
  loop_.reset();
  EXPECT_NE(loop_.navigation().report.reason.find("reset"), std::string::npos);
}

}  // namespace
}  // namespace evsim
