// The detector and its display: from a frame's line integrals to the gray
// image a clinician sees (mono8). The detector measures I / I0 = exp(-A);
// the display shows its logarithm, windowed as clinical systems do: the
// body's attenuation along the central ray (A_ref,
// XrayRenderer::referenceAttenuation) at kBackgroundGray, and
// kGrayPerAttenuation gray levels darker per unit of attenuation beyond it,
// so devices and contrast show dark on a light background as in fluoroscopy.
// Given the body's own attenuation, the display compresses its range
// (kEqualization of its variation across the image taken off, as the
// harmonisation filters of clinical systems do): a faint background in
// which thin devices stay visible from the edge of the body to its middle. Optional, seeded: the
// focal spot's and the detector's blur (Gaussian, before detection) and quantum noise (Poisson,
// with `photons` quanta per pixel at A_ref).
#pragma once

#include <cstdint>
#include <vector>

#include "endovascular_sim/imaging/xray_renderer.h"

namespace evsim {

constexpr double kBackgroundGray = 200.0;
constexpr double kGrayPerAttenuation = 100.0;
constexpr double kEqualization = 0.85;
/// A roadmap's vessels lighten the live image by up to this many gray
/// levels (a dense vessel almost all of it), so that the devices inside
/// them still show dark, as on a subtracted roadmap.
constexpr double kRoadmapLift = 45.0;

/// Gray levels of a frame; `frame_index` seeds the noise (the same frame
/// index and seed give the same image). A roadmap (a stored angiogram's
/// `contrast` part, same size) is shown light over the live image, as the
/// subtracted (inverted) angiogram of a roadmap display.
std::vector<std::uint8_t> detectorGray(const XrayFrame& frame, const XraySpec& spec,
                                       double reference_attenuation, long frame_index,
                                       const std::vector<float>* roadmap = nullptr,
                                       const std::vector<float>* body = nullptr);

}  // namespace evsim
