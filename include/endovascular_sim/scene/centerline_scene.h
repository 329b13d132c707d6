// A scene around a bare centreline file (a patient's `.vtp` or `.vtk`, or
// an SWC tree): what the node's `load_scene` builds when it is given a
// centreline instead of a scene. The vessels are the file's tree (its units
// declared, never guessed; the inlet its widest end; branches named
// `branch_<id>` by their ids); everything else (time step, effects, contact
// and sleep options, devices, script, X-ray) comes from a base scene, whose
// outermost devices enter at the inlet. No targets (the base's name its own
// vessels), no vessel motion (it moved the base's vessels).
#pragma once

#include <map>
#include <string>

#include "endovascular_sim/scene/scene_file.h"

namespace evsim {

struct CenterlineSceneRequest {
  std::string centerline;  // the file (.vtp, .vtk, .swc)
  std::string units;       // m, cm, mm or um: required for VTK (SWC: "" reads its header)
  std::string radius_array{"MaximumInscribedSphereRadius"};  // VTK: the radius point data
  std::string frame;  // the file's anatomical frame (patient_frame.h; "": the file's own)
  /// VTK: branch id -> vessel name; one name may go to a chain of
  /// consecutive branches (the arch a segmentation splits at its ostia).
  std::map<int, std::string> names;
};

/// Reads one "ID: NAME" entry of a branch's name into *names; false (and
/// *why) for a malformed entry or a branch named twice.
bool parseBranchName(const std::string& entry, std::map<int, std::string>* names,
                     std::string* why);

/// True for a path that names a centreline file rather than a scene.
bool isCenterlinePath(const std::string& path);

/// [m] per file unit for m, cm, mm, um; 0 for anything else.
double lengthUnit(const std::string& name);

/// The scene; throws LoadError naming the file and the field (units
/// missing or unknown, no such file, an empty radius array name, a frame
/// that is no orientation code, a name that is no vessel name). The tree
/// itself is read when the scene is built (buildSceneModel), where a bad
/// file is refused naming it.
SceneSpec centerlineScene(const SceneSpec& base, const CenterlineSceneRequest& request);

}  // namespace evsim
