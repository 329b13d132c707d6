#include "scene_source.h"

#include "endovascular_sim/scene/centerline_scene.h"

namespace evsim {

SceneSpec sceneSpecOf(const std::string& scene, const CenterlineSource& c) {
  if (!isCenterlinePath(scene)) return loadSceneFile(resolveScenePath(scene));
  const SceneSpec base = loadSceneFile(resolveScenePath(c.base));
  CenterlineSceneRequest request;
  request.centerline = scene;
  request.units = c.units;
  request.radius_array = c.radius_array;
  request.frame = c.frame;
  return centerlineScene(base, request);
}

}  // namespace evsim
