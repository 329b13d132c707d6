#include "scene_source.h"

#include "endovascular_sim/scene/centerline_scene.h"

namespace evsim {

SceneSpec sceneSpecOf(const std::string& scene, const CenterlineSource& c) {
  if (!isCenterlinePath(scene)) return loadSceneFile(resolveScenePath(scene));
  const SceneSpec base = loadSceneFile(resolveScenePath(c.base));
  return centerlineScene(base, {scene, c.units, c.radius_array});
}

}  // namespace evsim
