// `evsim arch`: generated aortic arches (geometry/arch_generator.h) written
// as a patient's files (scene/arch_scene.h): a line per arch, its variant
// and files.
#include <iostream>

#include "commands.h"
#include "endovascular_sim/scene/arch_scene.h"
#include "output_paths.h"

namespace evsim {

int archCommand(const ArchOptions& o) {
  const std::string why = prepareOutputFolder(o.out);
  if (!why.empty()) {
    std::cerr << "evsim: arch --out: " << why << "\n";
    return kExitBadInput;
  }
  ArchDrawOptions draw;
  draw.type = o.type;
  draw.bovine = o.bovine;
  draw.aberrant_rsa = o.aberrant_rsa;
  for (int k = 0; k < o.count; ++k) {
    const ArchParameters p = drawArch(o.seed + k, draw);
    const ArchScenes files = writeArchScenes(p, o.out);
    std::cout << "arch " << p.seed << ": " << p.summary() << "\n  " << files.centerline << "\n";
    for (const auto& [catheter, scene] : files.catheter_scene) {
      std::cout << "  " << scene << " (";
      bool first = true;
      for (const auto& [target, s] : files.target_scene)
        if (s == scene) std::cout << (first ? "" : ", ") << target, first = false;
      std::cout << ")\n";
    }
  }
  return kExitOk;
}

}  // namespace evsim
