// Numbers and ranges as text (core/number_text.h).
#include "endovascular_sim/core/number_text.h"

#include <cmath>
#include <cstdio>
#include <cstring>

namespace evsim {

std::string numberText(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  const double a = std::abs(v);
  char buf[32];
  if (a != 0.0 && (a < 1e-3 || a >= 1e6)) {
    std::snprintf(buf, sizeof buf, "%.6e", v);
    std::string mantissa(buf, std::strchr(buf, 'e'));
    while (mantissa.back() == '0') mantissa.pop_back();
    if (mantissa.back() == '.') mantissa.pop_back();
    return mantissa + "e" + std::to_string(static_cast<int>(std::floor(std::log10(a) + 1e-12)));
  }
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

namespace {
std::string withUnit(const std::string& text, const std::string& unit) {
  return unit.empty() ? text : text + " " + unit;
}
}  // namespace

std::string rangeText(double min, double max, bool min_open, bool max_open,
                      const std::string& unit) {
  const bool lo = std::isfinite(min), hi = std::isfinite(max);
  if (lo && hi)
    return withUnit(std::string(min_open ? "(" : "[") + numberText(min) + ", " + numberText(max) +
                        (max_open ? ")" : "]"),
                    unit);
  if (lo) return withUnit((min_open ? "above " : "at least ") + numberText(min), unit);
  if (hi) return withUnit((max_open ? "below " : "at most ") + numberText(max), unit);
  return "";
}

bool inRange(double v, double min, double max, bool min_open, bool max_open) {
  return (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
}

}  // namespace evsim
