// Device pairs as contacts (the effect 'device_contact'): found at a
// configuration between sample points or elements (contact.element_pairs;
// device_pairs.h), added to the loop's contacts and re-detected in its
// passes. Internal to the contact solver (contact_detection.cpp).
#pragma once

#include <array>
#include <vector>

#include "activation_loop.h"
#include "device_pairs.h"

namespace evsim::activation {

/// A device pair found at x, between sample points or elements' axes.
struct FoundPair {
  std::array<int, 4> key;  // (device, sample or element, device, sample or element)
  int device_a, sample_a, element_a, device_b, sample_b, element_b;
  SamplePoint on_a, on_b;  // the pair's points
  Vec3 at_b;               // b's point [m]
  Vec3 normal;             // from b toward a
  double depth;            // r_a + r_b - distance [m]
};

/// The device pairs at x within `margin` [m] (see pair_detection.cpp);
/// with element pairs and the axes at the step's start `from`, also those
/// that crossed since: the ones overlapping at x, and with `passed_through`
/// those apart there too (device_pairs.h). `keep_candidates`: the pairs'
/// candidates (of elements or of sample points) kept from pass to pass and
/// from step to step (pair_detection.cpp). `positions`: the sample points
/// at x, when the pass has them.
std::vector<FoundPair> devicePairs(const ContactProblem& pb, bool element_pairs,
                                   const std::vector<DeviceState>& x, double margin,
                                   const pairs::StartAxes* from = nullptr,
                                   bool passed_through = true, bool keep_candidates = false,
                                   SamplePositions* positions = nullptr);

/// The axes at the step's start for element pairs' swept test, computed on
/// first use in the step (none for sample points).
const pairs::StartAxes* stepStartAxes(const ContactProblem& pb, const ContactOptions& o,
                                      LoopState* s);

/// The previous step's device pairs that carried a force start the loop,
/// at the same points (of the two axes, or the two sample points), with
/// the normal devicePairs gives them at x_t (between the axes' points, or
/// the stretches the sample points stand for) and their force as the LCP's
/// warm start (as a wall contact does: contact_solver.h, "persist"), where
/// at the loop's first iterate their points lie within the larger radius of
/// touching. The free motion of a packed coil springs its turns open; found
/// afresh there, the contacts that hold them came back one activation loop
/// at a time. A pair the first iterate carried farther apart (a coil's
/// turns sliding along each other move up to half a millimetre in a step)
/// would be a row with nothing to hold.
void keepPairs(const ContactProblem& pb, bool element_pairs, LoopState* s);

/// A new pair contact in the loop's contacts.
void addPair(const FoundPair& f, LoopState* s);

/// Element pairs: a new pair found at the loop's first iterate next to a
/// pair kept from the last step with a force (one element along on either
/// axis, or on both), that force not yet taken over, takes it over as its
/// warm start. The two axes' closest points slid past a node since the
/// last step: a coil's turns sliding along each other move up to half a
/// millimetre a step, and the force that held them holds them at the
/// neighbouring element pair now. Started from zero there, and from the
/// old force at the pair left behind, each such contact cost the first
/// loop's LCP an activation and a deactivation. `kept`: the contacts
/// [kept[0], kept[1]) keepPairs added. Returns whether it took one over.
bool takeOverSlidForce(const FoundPair& f, std::array<int, 2> kept, LoopState* s);

/// Device pairs closer than the sum of their radii less the tolerance
/// (options.pair_tolerance, at least penetration_tolerance) at the loop's
/// x: a pair's points and normal moved to where they are at x once a step,
/// or a new pair. Returns false when there is one.
bool redetectPairs(const ContactProblem& pb, const ContactOptions& o, LoopState* s);

}  // namespace evsim::activation
