// Material and hollow circular cross-section of a beam, and the stiffnesses
// derived from them. Declared and documented in
// endovascular_sim/mechanics/beam_section.h.
#include "endovascular_sim/mechanics/beam_section.h"

#include <cmath>

namespace evsim {

double BeamSection::area() const {
  return M_PI * (outer_radius * outer_radius - inner_radius * inner_radius);
}

double BeamSection::secondMoment() const {
  return 0.25 * M_PI * (std::pow(outer_radius, 4) - std::pow(inner_radius, 4));
}

double BeamSection::polarMoment() const { return 2.0 * secondMoment(); }

double BeamSection::poissonRatio() const { return young_modulus / (2.0 * shear_modulus) - 1.0; }

double BeamSection::shearCoefficient() const {
  const double nu = poissonRatio();
  const double m = inner_radius / outer_radius;
  const double m2 = m * m;
  const double p = (1.0 + m2) * (1.0 + m2);
  return 6.0 * (1.0 + nu) * p / ((7.0 + 6.0 * nu) * p + (20.0 + 12.0 * nu) * m2);
}

Vec3 BeamSection::stretchShearStiffness() const {
  const double ga = shearCoefficient() * shear_modulus * area();
  return Vec3(young_modulus * area(), ga, ga);
}

Vec3 BeamSection::bendTwistStiffness() const {
  const double ei = young_modulus * secondMoment();
  return Vec3(shear_modulus * polarMoment(), ei, ei);
}

}  // namespace evsim
