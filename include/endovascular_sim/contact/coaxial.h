// Coaxial devices: an inner device (a guidewire in a catheter, a coil in a
// microcatheter) enters through its outer device's introducer and must stay
// inside the outer device's lumen where the two overlap.
//
// Model: contact between the two devices, through the same LCP as the wall
// and device-device contacts (and with Coulomb friction when that effect is
// on). Where they overlap - inner material that has passed the access point
// (path length a = s - (length - inserted) > 0) but not the outer device's
// tip (a < the outer's inserted length) - every inner sample point p must
// satisfy
//     |across| <= r_lumen - r,   across = (p - c) - ((p - c) . t) t,
// with c the closest point of the outer device's axis (its cubic Hermite
// curve) and t the axis' tangent there. It is linearised as a unilateral
// contact between p and c with the normal n = -across / |across| (toward the
// axis):  n . (p - c) + (r_lumen - r) >= 0, the circle's tangent plane where
// the point lies. As on vessel walls, a point still beyond the lumen after a
// loop has its contact moved to where it now lies, once, and then gets a
// second plane. With clearances below about 50 um and steps of 1 ms the free
// motion carries points across the whole lumen in one step; the planes then
// chatter (a wire in a catheter kept about 1e-5 J of kinetic energy):
// tight fits need steps of 0.2 ms (test/core/contact/coaxial_test.cpp).
//
// What follows from it: where the inner device lies against the lumen the
// two bend together and their stiffnesses add (a wire straightens a
// catheter's shaped tip); beyond the outer tip the inner device is free.
// Neglected: the clearance's effect on the lumen's own shape (the lumen is
// the outer device's axis swept by a circle), the fluid in the lumen, and
// contact between the inner device and the outer device's end face (the
// inner device can only leave through the tip).
#pragma once

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "endovascular_sim/mechanics/introducer.h"

namespace evsim {

/// Where an inner device's sample point lies in its outer device's lumen.
struct LumenLocation {
  bool inside{false};           // in the overlap: the lumen constrains it
  SamplePoint axis;             // closest point of the outer axis; radius = lumen radius,
                                // friction = the lumen's Coulomb coefficient
  Vec3 center{Vec3::Zero()};    // that point [m]
  Vec3 tangent{Vec3::UnitX()};  // unit tangent of the outer axis there
  Vec3 across{Vec3::Zero()};    // p - center across the axis [m]
  double clearance{0.0};        // r_lumen - r [m]
  Vec3 normal{Vec3::Zero()};    // -across / |across|: toward the axis
  /// How far the point lies beyond the lumen [m] (<= 0 inside).
  double excess() const { return across.norm() - clearance; }
};

/// Path length of a material coordinate past the access point [m].
double pathLength(const DeviceModel& model, const DeviceState& state, double s);

/// Material coordinate of a sample point [m].
double materialCoordinate(const DeviceModel& model, const SamplePoint& s);

/// Locates an inner sample point (in configuration x_inner) in the lumen of
/// the outer device (in x_outer).
LumenLocation locateInLumen(const DeviceModel& inner, const DeviceState& x_inner,
                            const SamplePoint& s, const DeviceModel& outer,
                            const DeviceState& x_outer);

/// The outer element's axis the last call of surelyWithinLumen used (the
/// next point of the inner device mostly lies along the same element).
/// Valid for one configuration of the outer device.
struct OuterAxisCache {
  int element{-1};
  HermiteAxis axis{};
  double lumen_radius{0.0};  // [m] the narrowest lumen within two elements of it
};

/// True when the inner sample point (in x_inner) is certainly not more than
/// `allowance` [m] beyond its outer device's lumen (in x_outer): outside the
/// overlap, or within r_lumen - r + allowance of one point of the guessed
/// outer element's axis (the distance across the axis at the closest point
/// is no longer). False: not known; locateInLumen tells. It saves the
/// closest-point search for the points that lie well inside. `position`:
/// the point in x_inner when the caller has it (else computed).
bool surelyWithinLumen(const DeviceModel& inner, const DeviceState& x_inner, const SamplePoint& s,
                       const DeviceModel& outer, const DeviceState& x_outer, double allowance,
                       OuterAxisCache* cache, const Vec3* position = nullptr);

/// An inner device at rest in its outer device: held nodes in the sheath,
/// inserted nodes on the outer device's axis where they overlap, and beyond
/// the outer tip the inner device's rest shape continuing from it.
DeviceState placeInside(const DeviceModel& inner, const Introducer& intro, double inserted_length,
                        double rotation_angle, const DeviceModel& outer,
                        const DeviceState& x_outer);

}  // namespace evsim
