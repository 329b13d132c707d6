// What the contact solver keeps between steps (contact/contact_workspace.h)
// belongs to the simulation, not to the thread that steps it: two
// simulations of a coil touching itself, stepped in turn on one thread,
// each step exactly as it does alone; and a copy of a running simulation
// (what deepcopy makes) steps as the original does to the last bit, its
// kept pair candidates copied with it.
#include <gtest/gtest.h>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

int devicePairs(const SimData& d) {
  int n = 0;
  for (const Contact& c : d.contacts) n += c.other_device >= 0 && !c.lumen;
  return n;
}

/// The largest distance between the nodes of two simulations [m] (0 when
/// they are the same to the last bit).
double apart(const SimData& a, const SimData& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.devices.size(); ++i)
    for (size_t k = 0; k < a.devices[i].position.size(); ++k)
      worst = std::max(worst, (a.devices[i].position[k] - b.devices[i].position[k]).norm());
  return worst;
}

TEST(ContactWorkspace, SimulationsSteppedInTurnOnOneThreadStepAsEachDoesAlone) {
  // aneurysm_packed: element pairs, their candidates kept from step to step.
  const SceneModel model = loadScene("aneurysm_packed");
  const int warmup = 800, steps = 600;  // the coil's turns touch from about t = 0.8 s
  SimData alone = makeData(model);
  for (int k = 0; k < warmup; ++k) ASSERT_EQ(step(model, &alone), StepStatus::kOk) << k;
  int pairs = 0;
  for (int k = 0; k < steps; ++k) {
    ASSERT_EQ(step(model, &alone), StepStatus::kOk) << k;
    pairs += devicePairs(alone);
  }
  ASSERT_GT(pairs, 0) << "no device pairs: the test would not exercise the kept candidates";
  // The other simulation ahead by 300 steps: its coil elsewhere, its
  // candidates of other points.
  SimData first = makeData(model), other = makeData(model);
  for (int k = 0; k < warmup; ++k) ASSERT_EQ(step(model, &first), StepStatus::kOk);
  for (int k = 0; k < warmup + 300; ++k) ASSERT_EQ(step(model, &other), StepStatus::kOk);
  for (int k = 0; k < steps; ++k) {
    ASSERT_EQ(step(model, &first), StepStatus::kOk) << k;
    ASSERT_EQ(step(model, &other), StepStatus::kOk) << k;
  }
  EXPECT_EQ(apart(first, alone), 0.0);
  std::printf("[ metric   ] %d device-pair contacts over %d steps, stepped in turn: 0 m apart\n",
              pairs, steps);
}

TEST(ContactWorkspace, ACopyOfARunningSimulationStepsAsTheOriginal) {
  const SceneModel model = loadScene("aneurysm_packed");
  SimData original = makeData(model);
  for (int k = 0; k < 900; ++k) ASSERT_EQ(step(model, &original), StepStatus::kOk);
  SimData copy = original;  // with its contact workspace
  int pairs = 0;
  for (int k = 0; k < 300; ++k) {
    ASSERT_EQ(step(model, &original), StepStatus::kOk) << k;
    ASSERT_EQ(step(model, &copy), StepStatus::kOk) << k;
    pairs += devicePairs(original);
  }
  EXPECT_GT(pairs, 0);
  EXPECT_EQ(apart(copy, original), 0.0);
}

}  // namespace
}  // namespace evsim
