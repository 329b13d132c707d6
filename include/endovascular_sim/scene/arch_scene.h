// A generated arch (geometry/arch_generator.h) as a patient's files: its
// centreline written as VMTK writes one (`.vtp`: one polyline per outlet
// from the aortic root, radii in MaximumInscribedSphereRadius, millimetres,
// the frame as field data), and scenes that load it the way
// docs/patient_anatomy.md tells for a real one (units, frame, inlet, branch
// names by id, the arch a chain of branches), with a guidewire in the
// catheter a clinician would take for each target at the femoral access.
#pragma once

#include <map>
#include <string>

#include "endovascular_sim/geometry/arch_generator.h"

namespace evsim {

/// Writes a centreline as VMTK's vmtkcenterlines does: a polyline from the
/// root to every leaf, points and radii in mm, a field-data string `frame`
/// when the centreline has one. Throws LoadError when it cannot be written.
void writeVmtkCenterline(const Centerline& centerline, const std::string& path);

struct ArchScenes {
  std::string centerline;                        // the .vtp
  std::map<std::string, std::string> catheter_scene;  // catheter -> scene file
  std::map<std::string, std::string> target_scene;    // target vessel -> scene file
};

/// Writes arch_<seed>.vtp and a scene per catheter the targets need
/// (arch_<seed>_<catheter>.yaml, its targets those the catheter is for)
/// into `dir`. The scenes' branch names are found by reading the .vtp back
/// as a scene would and matching each branch to the generated vessel it
/// runs along.
ArchScenes writeArchScenes(const ArchParameters& p, const std::string& dir);

}  // namespace evsim
