// Variants of a scene for benchmarks and sweeps: the same scene with another
// discretisation.
#pragma once

#include "endovascular_sim/scene/scene_file.h"

namespace evsim {

/// Scales every device's element counts so that each has about `elements`.
void setElementCount(SceneSpec* spec, int elements);

/// Elements of the scene's first device.
int elementCount(const SceneSpec& spec);

}  // namespace evsim
