// Sleep (SleepOptions): a scene at rest stops solving steps until something
// wakes it. Checked against the same run with sleep off (the reference):
// the state it sleeps in and the state after it wakes agree; while it
// sleeps nothing is computed (the gravity counter stands still); a changed
// command wakes it, a repeated one does not; moving vessels never sleep;
// the sleep survives a state file; a target's dwell ends while it sleeps.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "endovascular_sim/sim/simulation.h"
#include "endovascular_sim/sim/state_file.h"

namespace evsim {
namespace {

SceneModel carotid(bool sleep) {
  SceneSpec spec = loadSceneFile(resolveScenePath("carotid"));
  spec.sleep.enabled = sleep;
  return buildSceneModel(spec);
}

/// Largest distance between the two runs' nodes [m].
double largestGap(const SimData& a, const SimData& b) {
  double gap = 0.0;
  for (size_t d = 0; d < a.devices.size(); ++d)
    for (size_t n = 0; n < a.devices[d].position.size(); ++n)
      gap = std::max(gap, (a.devices[d].position[n] - b.devices[d].position[n]).norm());
  return gap;
}

void stepBoth(const SceneModel& ma, SimData* a, const SceneModel& mb, SimData* b, long steps) {
  for (long k = 0; k < steps; ++k) {
    ASSERT_EQ(step(ma, a), StepStatus::kOk) << a->last_error;
    ASSERT_EQ(step(mb, b), StepStatus::kOk) << b->last_error;
  }
}

// The carotid wire is fully inserted at 9.3 s and rests from then on.
TEST(Sleep, ARestingWireSleepsWhereTheReferenceRestsAndWakesOnACommand) {
  const SceneModel sleepy = carotid(true), awake = carotid(false);
  SimData s = makeData(sleepy), r = makeData(awake);
  stepBoth(sleepy, &s, awake, &r, 11000);
  ASSERT_TRUE(s.asleep) << "the wire rests from about 9.5 s";
  EXPECT_FALSE(r.asleep);
  EXPECT_LT(largestGap(s, r), 1e-6);

  // Asleep, steps compute nothing: the free motion (gravity) is not entered.
  const long gravity = s.effect_calls.gravity;
  stepBoth(sleepy, &s, awake, &r, 200);
  EXPECT_EQ(s.effect_calls.gravity, gravity);
  EXPECT_TRUE(s.stats.asleep);
  EXPECT_EQ(s.stats.contact.active_contacts, r.stats.contact.active_contacts);  // the kept contacts
  EXPECT_DOUBLE_EQ(s.time, r.time);

  // The joystick repeats its last command: no wake. A changed one wakes it.
  const DriveCommand standing = s.commands[0];
  ASSERT_EQ(setCommand(sleepy, &s, "guidewire", standing), "");
  EXPECT_TRUE(s.asleep);
  const DriveCommand retract{DriveCommand::Mode::kVelocity, -0.01, 0.0};
  ASSERT_EQ(setCommand(sleepy, &s, "guidewire", retract), "");
  ASSERT_EQ(setCommand(awake, &r, "guidewire", retract), "");
  EXPECT_FALSE(s.asleep);
  stepBoth(sleepy, &s, awake, &r, 500);  // 5 mm back out
  EXPECT_FALSE(s.stats.asleep);
  EXPECT_GT(s.effect_calls.gravity, gravity);
  const double gap = largestGap(s, r);
  std::printf("[ metric   ] sleeping and reference runs: %.3g um apart after waking\n", gap * 1e6);
  EXPECT_LT(gap, 1e-6);
}

// A target's dwell goes on while the scene sleeps: the sleeping run reaches
// every target of the carotid's named vessels when the reference does, and
// one of them only after the sleep began (the dwell ends asleep).
TEST(Sleep, ATargetsDwellEndsWhileTheSceneSleeps) {
  const double dwell = 10.0;  // [s] the tip is in the left subclavian from 2 s, at rest from 10 s
  auto withTargets = [&](bool sleep) {
    SceneSpec spec = loadSceneFile(resolveScenePath("carotid"));
    spec.sleep.enabled = sleep;
    const SceneModel plain = buildSceneModel(spec);
    spec.targets.clear();
    for (const NamedVessel& v : plain.atlas->vessels()) {
      TargetSpec t;
      t.vessel = v.name;
      t.depth = 0.001;
      t.dwell = dwell;
      spec.targets.push_back(t);
    }
    return buildSceneModel(spec);
  };
  const SceneModel sleepy = withTargets(true), awake = withTargets(false);
  SimData s = makeData(sleepy), r = makeData(awake);
  double fell_asleep = -1.0;  // [s]
  for (long k = 0; k < 16000; ++k) {
    ASSERT_EQ(step(sleepy, &s), StepStatus::kOk) << s.last_error;
    ASSERT_EQ(step(awake, &r), StepStatus::kOk) << r.last_error;
    if (s.asleep && fell_asleep < 0.0) fell_asleep = s.time;
  }
  ASSERT_GT(fell_asleep, 0.0);
  int reached_asleep = 0;
  for (size_t k = 0; k < s.targets.size(); ++k) {
    EXPECT_EQ(s.targets[k].reached, r.targets[k].reached) << sleepy.targets[k].spec.vessel;
    EXPECT_NEAR(s.targets[k].reached_time, r.targets[k].reached_time, 1.5e-3)
        << sleepy.targets[k].spec.vessel;
    reached_asleep += s.targets[k].reached && s.targets[k].reached_time > fell_asleep;
  }
  EXPECT_GE(reached_asleep, 1) << "asleep from " << fell_asleep << " s";
}

TEST(Sleep, MovingVesselsNeverSleep) {
  const SceneModel m = loadScene("network");
  ASSERT_TRUE(m.effects.vessel_motion);
  EXPECT_FALSE(m.sleep.enabled);
}

TEST(Sleep, AStateFileKeepsTheSleep) {
  const SceneModel m = carotid(true);
  SimData a = makeData(m);
  for (long k = 0; k < 11000; ++k) ASSERT_EQ(step(m, &a), StepStatus::kOk) << a.last_error;
  ASSERT_TRUE(a.asleep);
  const std::string path = (std::filesystem::temp_directory_path() / "evsim_sleep_state.txt");
  ASSERT_TRUE(saveState(m, a, path));
  SimData b = makeData(m);
  loadState(m, path, &b);
  EXPECT_TRUE(b.asleep);
  EXPECT_EQ(b.resting_steps, a.resting_steps);

  // A version 1 file (no sleep fields) loads awake.
  std::vector<std::string> lines;
  {
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  ASSERT_GT(lines.size(), 3u);
  lines[0] = "evsim_state 1";
  for (int k = 0; k < 2; ++k) lines[2].erase(lines[2].rfind(' '));
  for (std::string& l : lines)  // (no pair contact's own point before version 3)
    if (l.rfind("contact ", 0) == 0)
      for (int k = 0; k < 4; ++k) l.erase(l.rfind(' '));
  {
    std::ofstream out(path);
    for (const std::string& l : lines) out << l << "\n";
  }
  SimData c = makeData(m);
  loadState(m, path, &c);
  EXPECT_FALSE(c.asleep);
  EXPECT_EQ(c.step, a.step);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace evsim
