// What a device is made of, as X-rays see it: the radiopaque materials a
// device section or a marker band may name, by elemental composition and
// density. Declared and documented in
// endovascular_sim/mechanics/radiopacity.h.
#include "endovascular_sim/mechanics/radiopacity.h"

namespace evsim {

const std::vector<XrayMaterial>& xrayMaterials() {
  // Compositions by mass; densities at room temperature. The alloys are the
  // ones device makers name (ASTM F2063 nitinol, AISI 304 steel, Pt-W 92/8
  // coil wire, Pt-Ir 90/10 marker bands); the polymer is polyether block
  // amide approximated by polyethylene's composition, and its radiopaque
  // grade holds 20 % barium sulfate by mass (makers use 20-40 %).
  static const std::vector<XrayMaterial> table = {
      {"polymer",
       "catheter shaft polymer (PEBA, as (CH2)n), no filler",
       {{6, 0.856}, {1, 0.144}},
       1010.0},
      {"polymer_barium",
       "catheter polymer with 20 % BaSO4 filler by mass",
       {{6, 0.685}, {1, 0.115}, {56, 0.1177}, {16, 0.0275}, {8, 0.0548}},
       1195.0},
      {"nitinol",
       "NiTi shape-memory alloy, 55 % Ni by mass (ASTM F2063)",
       {{28, 0.55}, {22, 0.45}},
       6450.0},
      {"steel",
       "AISI 304 stainless steel",
       {{26, 0.70}, {24, 0.19}, {28, 0.09}, {25, 0.02}},
       8000.0},
      {"platinum", "Pt-W 92/8, embolisation coil wire", {{78, 0.92}, {74, 0.08}}, 21300.0},
      {"platinum_iridium",
       "Pt-Ir 90/10, marker bands and wire tip coils",
       {{78, 0.90}, {77, 0.10}},
       21560.0},
  };
  return table;
}

int findXrayMaterial(const std::string& name) {
  const auto& table = xrayMaterials();
  for (size_t i = 0; i < table.size(); ++i)
    if (table[i].name == name) return static_cast<int>(i);
  return -1;
}

}  // namespace evsim
