// Shared fixtures for the core tests.
#pragma once

#include <random>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/beam_section.h"
#include "endovascular_sim/mechanics/so3.h"

namespace evsim::test {

/// Solid wire: E [Pa], Poisson 0.3, radius [m], density [kg/m^3].
inline BeamSection wireSection(double young_modulus, double radius, double density = 6500.0) {
  BeamSection s;
  s.young_modulus = young_modulus;
  s.shear_modulus = young_modulus / (2.0 * 1.3);
  s.outer_radius = radius;
  s.density = density;
  return s;
}

inline Mat3 randomRotation(std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return expSO3(Vec3(n(*rng), n(*rng), n(*rng)));
}

}  // namespace evsim::test
