// Linear attenuation coefficients at the beam's effective energy, from
// xraylib's photon cross sections (total, coherent scattering included: the
// NIST XCOM data, Berger & Hubbell) and NIST's tissue compositions. Declared
// and documented in endovascular_sim/imaging/attenuation.h.
#include "endovascular_sim/imaging/attenuation.h"

#include <xraylib.h>

#include <stdexcept>
#include <string>

#include "endovascular_sim/mechanics/radiopacity.h"

namespace evsim {

namespace {

/// cm^2/g (xraylib's unit) to m^2/kg.
constexpr double kCm2PerGram = 0.1;

double checked(double value, xrl_error* error, const std::string& what) {
  if (error) {
    const std::string message = error->message ? error->message : "unknown error";
    xrl_error_free(error);
    throw std::invalid_argument("xraylib: " + what + ": " + message);
  }
  return value;
}

/// Linear coefficient [1/m] of a NIST compound (xraylib's list).
double nistCompound(const char* name, double energy_kev) {
  xrl_error* error = nullptr;
  compoundDataNIST* c = GetCompoundDataNISTByName(name, &error);
  checked(0.0, error, name);
  double mass = 0.0;
  for (int i = 0; i < c->nElements; ++i)
    mass += c->massFractions[i] * elementMassAttenuation(c->Elements[i], energy_kev);
  const double density = c->density * 1000.0;  // g/cm^3 -> kg/m^3
  FreeCompoundDataNIST(c);
  return mass * density;
}

}  // namespace

double elementMassAttenuation(int Z, double energy_kev) {
  xrl_error* error = nullptr;
  const double cm2_per_g = CS_Total(Z, energy_kev, &error);
  return checked(cm2_per_g, error, "Z = " + std::to_string(Z)) * kCm2PerGram;
}

AttenuationTable attenuationAt(double energy_kev) {
  if (!(energy_kev >= 35.0 && energy_kev <= 120.0))
    throw std::invalid_argument("beam energy must lie in [35, 120] keV, got " +
                                std::to_string(energy_kev));
  AttenuationTable t;
  t.energy_kev = energy_kev;
  for (const XrayMaterial& m : xrayMaterials()) {
    double mass = 0.0;
    for (const auto& [Z, fraction] : m.elements)
      mass += fraction * elementMassAttenuation(Z, energy_kev);
    t.device_material.push_back(mass * m.density);
  }
  t.soft_tissue = nistCompound("Tissue, Soft (ICRP)", energy_kev);
  t.blood = nistCompound("Blood (ICRP)", energy_kev);
  t.bone = nistCompound("Bone, Cortical (ICRP)", energy_kev);
  t.iodine_mass = elementMassAttenuation(53, energy_kev);
  return t;
}

}  // namespace evsim
