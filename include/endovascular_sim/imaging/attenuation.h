// Linear attenuation coefficients at the beam's effective energy, from
// xraylib's photon cross sections (total, coherent scattering included:
// the NIST XCOM data, Berger & Hubbell) and NIST's tissue compositions.
// Beer-Lambert: I = I0 exp(-sum mu_k L_k) along a ray.
#pragma once

#include <vector>

namespace evsim {

/// Mass attenuation coefficient [m^2/kg] of element Z at E [keV].
double elementMassAttenuation(int Z, double energy_kev);

struct AttenuationTable {
  double energy_kev{60.0};
  std::vector<double> device_material;  // [1/m] per xrayMaterials() entry
  double soft_tissue{0.0};              // [1/m] ICRP soft tissue (the body's background)
  double blood{0.0};                    // [1/m] ICRP blood
  double bone{0.0};                     // [1/m] ICRP cortical bone
  double iodine_mass{0.0};              // [m^2/kg] iodine (contrast: times its concentration)
};

/// The coefficients at one energy [keV], in [35, 120].
AttenuationTable attenuationAt(double energy_kev);

}  // namespace evsim
