// Variants of a scene for benchmarks and sweeps: the same scene with another
// discretisation, other effects, or its script's speeds perturbed.
#pragma once

#include "endovascular_sim/scene/scene_file.h"

namespace evsim {

/// Scales every device's element counts so that each has about `elements`.
void setElementCount(SceneSpec* spec, int elements);

/// Scales the speed of every velocity command of the script by (1 +
/// relative): a copy of the scene whose path differs by round-off at
/// first (`evsim bench --copies`).
void perturbScript(SceneSpec* spec, double relative);

/// Elements of the scene's first device.
int elementCount(const SceneSpec& spec);

/// Replaces the scene's effects by a comma-separated list ("" = none);
/// returns why it cannot ("" when done): an unknown name, or vessel_motion
/// without motion regions.
std::string setEffects(SceneSpec* spec, const std::string& list);

}  // namespace evsim
