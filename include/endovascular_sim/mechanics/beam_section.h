// Material and hollow circular cross-section of a beam, and the stiffnesses
// derived from them. Local axes: x along the beam, y and z across it.
#pragma once

#include "endovascular_sim/core/types.h"

namespace evsim {

struct BeamSection {
  double young_modulus{0.0};  // E [Pa]
  double shear_modulus{0.0};  // G [Pa]
  double outer_radius{0.0};   // [m]
  double inner_radius{0.0};   // [m], 0 for a solid wire
  double density{0.0};        // [kg/m^3]

  double area() const;          // [m^2]
  double secondMoment() const;  // I about y or z [m^4]
  double polarMoment() const;   // J = 2 I [m^4]
  double poissonRatio() const;  // E / 2G - 1 [-]
  /// Cowper's Timoshenko shear coefficient of a hollow circle [-].
  double shearCoefficient() const;

  /// (EA, kGA, kGA) [N]: axial and shear stiffness.
  Vec3 stretchShearStiffness() const;
  /// (GJ, EI, EI) [N m^2]: torsion and bending stiffness.
  Vec3 bendTwistStiffness() const;
};

}  // namespace evsim
