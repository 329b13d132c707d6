// Numbers and ranges as the scene files and their messages write them.
#pragma once

#include <string>

namespace evsim {

/// A number as a reader writes it: 0.04, 3600, 1e-5, 1e6 (exponents for
/// magnitudes below 1e-3 or from 1e6; six significant digits at most).
std::string numberText(double v);

/// "[0, 0.04] s", "(0, 1]", "at least 1e-5 m", "below 3"; "" without
/// bounds (an infinite bound is none).
std::string rangeText(double min, double max, bool min_open, bool max_open,
                      const std::string& unit);

/// Whether v lies in the range (a NaN never does).
bool inRange(double v, double min, double max, bool min_open, bool max_open);

}  // namespace evsim
