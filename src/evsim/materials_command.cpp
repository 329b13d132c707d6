// `evsim materials`: the radiopaque materials a device file may name and the
// media of the body, with their attenuation at a beam energy (xraylib).
#include <cstdio>

#include "commands.h"
#include "endovascular_sim/imaging/attenuation.h"
#include "endovascular_sim/mechanics/radiopacity.h"

namespace evsim {

int materialsCommand(double energy_kev) {
  const AttenuationTable t = attenuationAt(energy_kev);
  std::printf("attenuation at %.1f keV (xraylib, NIST XCOM cross sections)\n", energy_kev);
  std::printf("%-18s %10s %12s %10s  %s\n", "material", "rho[kg/m3]", "mu/rho[m2/kg]", "mu[1/mm]",
              "what it stands for");
  const auto& table = xrayMaterials();
  for (size_t i = 0; i < table.size(); ++i)
    std::printf("%-18s %10.0f %12.4g %10.4g  %s\n", table[i].name.c_str(), table[i].density,
                t.device_material[i] / table[i].density, t.device_material[i] * 1e-3,
                table[i].description.c_str());
  std::printf("%-18s %10s %12s %10.4g  %s\n", "soft_tissue", "", "", t.soft_tissue * 1e-3,
              "ICRP soft tissue: the body's background");
  std::printf("%-18s %10s %12s %10.4g  %s\n", "blood", "", "", t.blood * 1e-3, "ICRP blood");
  std::printf("%-18s %10s %12.4g %10s  %s\n", "iodine", "", t.iodine_mass, "",
              "contrast: mu = mu/rho x its concentration (150 kg/m^3: 1.14/cm at 60 keV)");
  return kExitOk;
}

}  // namespace evsim
