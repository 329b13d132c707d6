// The detector and its display: from a frame's line integrals to the gray
// image a clinician sees (mono8). Declared and documented in
// endovascular_sim/imaging/detector.h.
#include "endovascular_sim/imaging/detector.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace evsim {

namespace {

/// Separable Gaussian blur of sigma [px], edges clamped.
void blur(std::vector<double>* image, int w, int h, double sigma) {
  const int radius = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k)
    sum += kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  for (double& k : kernel) k /= sum;
  std::vector<double> tmp(image->size());
  auto pass = [&](const std::vector<double>& in, std::vector<double>* out, bool rows) {
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        double acc = 0.0;
        for (int k = -radius; k <= radius; ++k) {
          const int uu = rows ? std::clamp(u + k, 0, w - 1) : u;
          const int vv = rows ? v : std::clamp(v + k, 0, h - 1);
          acc += kernel[k + radius] * in[static_cast<size_t>(vv) * w + uu];
        }
        (*out)[static_cast<size_t>(v) * w + u] = acc;
      }
  };
  pass(*image, &tmp, true);
  pass(tmp, image, false);
}

}  // namespace

std::vector<std::uint8_t> detectorGray(const XrayFrame& frame, const XraySpec& spec,
                                       double reference_attenuation, long frame_index,
                                       const std::vector<float>* roadmap,
                                       const std::vector<float>* body) {
  const int w = frame.width, h = frame.height;
  std::vector<double> intensity(frame.attenuation.size());
  for (size_t p = 0; p < intensity.size(); ++p)
    intensity[p] = std::exp(-(frame.attenuation[p] - reference_attenuation));
  if (spec.blur > 0.0) blur(&intensity, w, h, spec.blur);
  if (spec.photons > 0.0) {
    std::mt19937_64 rng(spec.seed * 0x9E3779B97F4A7C15ULL +
                        static_cast<unsigned long>(frame_index));
    for (double& i : intensity) {
      const double mean = spec.photons * i;
      // Poisson counts; their normal limit above 50 quanta (same mean and variance).
      const double count =
          mean < 50.0 ? static_cast<double>(std::poisson_distribution<long>(mean)(rng))
                      : std::max(0.0, std::normal_distribution<double>(mean, std::sqrt(mean))(rng));
      i = count / spec.photons;
    }
  }
  std::vector<std::uint8_t> gray(intensity.size());
  for (size_t p = 0; p < gray.size(); ++p) {
    // The log of the detected intensity (A again, with blur and noise), windowed.
    double a = -std::log(std::max(intensity[p], 1e-6));
    if (body) a -= kEqualization * ((*body)[p] - reference_attenuation);
    double g = kBackgroundGray - kGrayPerAttenuation * a;
    if (roadmap) g += kRoadmapLift * (1.0 - std::exp(-(*roadmap)[p]));  // the vessels light
    gray[p] = static_cast<std::uint8_t>(std::clamp(std::lround(g), 0L, 255L));
  }
  return gray;
}

}  // namespace evsim
