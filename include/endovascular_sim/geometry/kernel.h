// The convolution kernel of the vessel surface and its closed-form integrals.
//
// K_R(r) = (1 - r^2/R^2)^3 for r < R, 0 beyond: compact support, C^2.
//   Segment primitive (a -> b):  f(P) = (1/R) int_0^L K_R(|P - a - t u|) dt,
//     which for an infinite straight line is (32/35) (1 - d^2/R^2)^(7/2),
//     d the distance to the line: the same profile for every width R.
//   Sphere primitive (centre c):  f(P) = w K_R(|P - c|).
// With the iso value T = (32/35) (1 - alpha^2)^(7/2), a straight vessel of
// radius rho modelled with R = rho / alpha has its iso-surface exactly at
// d = rho. Values and gradients are closed forms (no quadrature).
#pragma once

#include "endovascular_sim/core/types.h"

namespace evsim {

struct FieldSample {
  double value{0.0};
  Vec3 gradient{Vec3::Zero()};  // [1/m]
};

/// Iso value for the normalised radius alpha = rho / R in (0, 1).
double isoValueForAlpha(double alpha);

/// Adds the segment primitive's value and gradient at p. R [m].
void addSegmentField(const Vec3& a, const Vec3& b, double R, const Vec3& p, FieldSample* out);

/// The same for the segment from a along the unit axis u over a length L > 0
/// [m] (u = (b - a) / L, L = |b - a|): a vessel that does not move keeps
/// them instead of deriving them at every evaluation.
void addSegmentFieldAlong(const Vec3& a, const Vec3& u, double L, double R, const Vec3& p,
                          FieldSample* out);

/// Adds the sphere primitive's value and gradient at p.
void addSphereField(const Vec3& c, double R, double weight, const Vec3& p, FieldSample* out);

/// Upper bounds of the spectral norm of the Hessian [1/m^2] of one primitive.
double segmentHessianBound(double R);
double sphereHessianBound(double R, double weight);

}  // namespace evsim
