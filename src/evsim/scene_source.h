// The scene an evsim command names: a shipped scene's name, a scene file,
// or a bare centreline file (.vtp, .vtk, .swc) placed in a base scene's
// devices and settings (scene/centerline_scene.h) — so a patient's
// centreline can be looked at (`evsim vessels`) and run (`evsim run`)
// before a scene is written for it.
#pragma once

#include <string>

#include "commands.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {

/// Throws LoadError naming the file and what is wrong.
SceneSpec sceneSpecOf(const std::string& scene, const CenterlineSource& centerline);

}  // namespace evsim
