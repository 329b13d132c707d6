// What a device is made of, as X-rays see it: the radiopaque materials a
// device section or a marker band may name, by elemental composition and
// density. The imaging layer turns them into attenuation coefficients at a
// beam energy (imaging/attenuation.h); nothing here depends on the energy.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace evsim {

struct XrayMaterial {
  std::string name;
  std::string description;                       // what it stands for, and the source
  std::vector<std::pair<int, double>> elements;  // (atomic number Z, mass fraction), sum 1
  double density{0.0};                           // [kg/m^3]
};

/// The materials a device file may name (`xray_material`, `<evsim_marker>`).
const std::vector<XrayMaterial>& xrayMaterials();

/// Index of a material by name in xrayMaterials(), -1 when unknown.
int findXrayMaterial(const std::string& name);

/// The material a section is made of when its file names none.
inline const char* kDefaultXrayMaterial = "polymer";

/// A radiopaque band on a device (a catheter's tip marker): it replaces the
/// section's material over [s_begin, s_end] of the material coordinate.
struct XrayMarker {
  double s_begin{0.0};  // [m] from the device's proximal end
  double s_end{0.0};    // [m]
  int material{-1};     // index into xrayMaterials()
};

}  // namespace evsim
