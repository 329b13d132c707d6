// `evsim bench SCENE --windows N`: the scene and its variants stepped from
// the same saved states of its run (bench_windows.cpp).
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

struct BenchWindows {
  int count{0};                       // windows (0: none)
  long steps{10};                     // steps stepped from each window's state
  std::vector<std::string> variants;  // scene files with the scene's devices
};

/// The variant scene files built, each checked to have the devices of
/// `model` (names and node counts); its name becomes the scene's (the
/// states it starts from are the scene's). "" or what is wrong.
std::string loadVariants(const SceneModel& model, const std::vector<std::string>& files,
                         std::vector<SceneModel>* variants);

/// Runs `model` over steps [0, warmup + steps) saving its state at
/// o.count steps spread over [warmup, warmup + steps - o.steps]; from each,
/// steps the scene and each of `variants` (o.variants, loaded) o.steps
/// steps, and prints per scene the loops after the first, late rows, mean
/// rows, halved steps, the deepest penetration a step ended with and the
/// step times' median, mean and p99, and whether the scene's windows
/// repeated the run's loops. Returns an evsim exit code (commands.h).
int benchWindows(const SceneModel& model, const std::vector<SceneModel>& variants,
                 const BenchWindows& o, long warmup, long steps, bool strict);

}  // namespace evsim
