// The node's simulation loop: fixed steps per frame, commands, refusals,
// reset, pause and solver options (no timing is asserted: waits are bounded
// polls, results are compared with the scene files and the commands sent).
#include "endovascular_sim/ros/simulation_loop.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <thread>

namespace evsim {
namespace {

/// Polls until the condition holds (at most `limit_s` of wall time).
bool eventually(const std::function<bool()>& condition, int limit_s = 30) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(limit_s);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

class Loop : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = std::make_shared<const SceneModel>(loadScene("free_insertion"));
    loop_.setScene(model_, /*use_script=*/false);
    loop_.start();
  }
  std::shared_ptr<const SceneModel> model_;
  SimulationLoop loop_{100.0};  // 100 Hz frames
};

TEST_F(Loop, FramesHoldTheScenesFixedSteps) {
  EXPECT_EQ(loop_.timing().steps_per_frame,
            static_cast<int>(std::lround(0.01 / model_->time_step)));
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().step >= 30; }));
  const FrameSnapshot f = loop_.snapshot();
  EXPECT_NEAR(f.time, f.step * model_->time_step, 1e-12);  // whole steps only
}

TEST_F(Loop, EveryStepsDriveWrenchIsKeptForThePublisher) {
  // The node publishes the drive's wrench at the simulation's rate: one
  // sample per step, stamped with the step's time, none lost between takes.
  loop_.takeWrenches();
  const long from = loop_.snapshot().step;
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().step >= from + 50; }));
  std::vector<WrenchSample> all;
  for (int take = 0; take < 3; ++take) {
    const auto samples = loop_.takeWrenches();
    ASSERT_EQ(samples.size(), model_->devices.size());
    all.insert(all.end(), samples[0].begin(), samples[0].end());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(all.size(), 50u);
  for (size_t k = 1; k < all.size(); ++k)
    EXPECT_NEAR(all[k].time - all[k - 1].time, model_->time_step, 1e-12) << k;
}

TEST_F(Loop, PositionCommandReachesItsTarget) {
  const double target = model_->initial_inserted_length[0] + 0.01;
  DriveCommand c;
  c.mode = DriveCommand::Mode::kPosition;
  c.insertion = target;
  EXPECT_EQ(loop_.setCommand("guidewire", c), "");
  ASSERT_TRUE(eventually(
      [&] { return std::abs(loop_.snapshot().devices[0].inserted_length - target) < 1e-12; }));
}

TEST_F(Loop, BadCommandsAreRefusedAndChangeNothing) {
  DriveCommand c;
  c.insertion = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(loop_.setCommand("guidewire", c).find("finite"), std::string::npos);
  c.insertion = 0.01;
  EXPECT_NE(loop_.setCommand("nope", c).find("unknown device 'nope'"), std::string::npos);
  c.insertion = 10.0 * model_->devices[0].max_insertion_speed;
  EXPECT_NE(loop_.setCommand("guidewire", c).find("exceeds the limit"), std::string::npos);
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().step >= 20; }));
  EXPECT_EQ(loop_.snapshot().devices[0].inserted_length, model_->initial_inserted_length[0]);
}

TEST_F(Loop, ResetReturnsToTheInitialState) {
  DriveCommand c;
  c.insertion = 0.02;  // [m/s]
  ASSERT_EQ(loop_.setCommand("guidewire", c), "");
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().time > 0.05; }));
  loop_.setPaused(true);
  loop_.reset();
  const FrameSnapshot f = loop_.snapshot();
  EXPECT_EQ(f.step, 0);
  EXPECT_EQ(f.devices[0].inserted_length, model_->initial_inserted_length[0]);
}

TEST_F(Loop, PauseHoldsSimulatedTime) {
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().step > 0; }));
  loop_.setPaused(true);
  const long held = loop_.snapshot().step;
  const long frames = loop_.timing().frames;
  ASSERT_TRUE(eventually([&] { return loop_.timing().frames >= frames + 5; }));
  EXPECT_EQ(loop_.snapshot().step, held);
  loop_.setPaused(false);
  ASSERT_TRUE(eventually([&] { return loop_.snapshot().step > held; }));
}

TEST_F(Loop, SolverOptionsAreValidatedBeforeTheyApply) {
  ContactOptions o = model_->contact;
  o.lcp.tolerance = -1.0;
  EXPECT_NE(loop_.setContactOptions(o).find("tolerance"), std::string::npos);
  EXPECT_EQ(loop_.model()->contact.lcp.tolerance, model_->contact.lcp.tolerance);
  o.lcp.tolerance = 1e-8;
  o.lcp.solver = LcpSolver::kPgs;
  EXPECT_EQ(loop_.setContactOptions(o), "");
  EXPECT_EQ(loop_.model()->contact.lcp.tolerance, 1e-8);
  EXPECT_EQ(loop_.model()->contact.lcp.solver, LcpSolver::kPgs);
  EXPECT_EQ(model_->contact.lcp.solver, LcpSolver::kStatusMethod);  // the old model is intact
}

TEST(LoopDetach, RefusedWhileInsideThenTheCoilIsCut) {
  auto model = std::make_shared<const SceneModel>(loadScene("aneurysm_coiling"));
  SimulationLoop loop(100.0);
  loop.setScene(model, /*use_script=*/true);  // the coil advances 10 mm/s, stops at 1.6 s
  loop.setPaused(true);
  loop.start();
  const FrameSnapshot before = loop.snapshot();
  EXPECT_NE(loop.detach("finishing_coil").find("still in the microcatheter"), std::string::npos);
  EXPECT_NE(loop.detach("microcatheter").find("no detach_section"), std::string::npos);
  EXPECT_NE(loop.detach("nope").find("unknown device"), std::string::npos);
  EXPECT_EQ(loop.snapshot().devices[1].cut_element, -1);
  EXPECT_EQ(loop.snapshot().step, before.step);
  loop.setPaused(false);
  // The scene's own detach is scripted at 1.65 s: detach between 1.6 and it.
  ASSERT_TRUE(eventually([&] { return loop.snapshot().time >= 1.6; }, 300));
  loop.setPaused(true);
  ASSERT_LT(loop.snapshot().time, 1.65);
  EXPECT_EQ(loop.detach("finishing_coil"), "");
  EXPECT_EQ(loop.snapshot().devices[1].cut_element, model->devices[1].detach_element);
  EXPECT_NE(loop.detach("finishing_coil").find("already"), std::string::npos);
  loop.stop();
}

TEST(LoopRecovery, ARejectedStepIsRecoveredAtOnceAndTold) {
  // One PGS sweep cannot solve the J-tip's first contact: every step with a
  // contact is rejected. The loop solves each such step at once with the
  // recovery options (the status method), as evsim does, says why the
  // scene's options failed, and runs on unpaused.
  auto model = std::make_shared<SceneModel>(loadScene("carotid_selective"));
  model->contact.lcp.solver = LcpSolver::kPgs;
  model->contact.lcp.max_iterations = 1;
  SimulationLoop loop(100.0);
  loop.setScene(model, /*use_script=*/true);
  loop.start();
  std::vector<std::string> told;
  auto tell = [&](const std::string& words) {
    for (const std::string& n : loop.takeNotices()) told.push_back(n);
    for (const std::string& n : told)
      if (n.find(words) != std::string::npos) return true;
    return false;
  };
  ASSERT_TRUE(eventually([&] { return tell("recovered"); }, 120)) << [&] {
    std::string all = loop.lastError();
    for (const std::string& n : told) all += "\n" + n;
    return all;
  }();
  EXPECT_TRUE(tell("rejected: "));
  EXPECT_TRUE(tell("iteration limit"));
  EXPECT_TRUE(tell("use the status method"));
  const double at = loop.snapshot().time;
  ASSERT_TRUE(eventually([&] { return loop.snapshot().time > at + 0.05; }, 120));
  EXPECT_FALSE(loop.snapshot().paused);
  loop.stop();
}

TEST(LoopRecovery, TheRecoveryStepUsesTheExactSolverWithMoreRoom) {
  SceneModel m = loadScene("carotid");
  m.contact.lcp.solver = LcpSolver::kPgs;
  m.contact.lcp.max_iterations = 1;
  m.effects.subdivision = false;
  const SceneModel r = recoveryModel(m);
  EXPECT_EQ(r.contact.lcp.solver, LcpSolver::kStatusMethod);
  EXPECT_EQ(r.contact.lcp.max_iterations, 0);  // automatic
  EXPECT_GE(r.contact.max_activation_loops, 40);
  EXPECT_GE(r.contact.max_subdivisions, 8);
  EXPECT_TRUE(r.effects.subdivision);
}

}  // namespace
}  // namespace evsim
