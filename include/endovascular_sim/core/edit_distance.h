// Edit distance between names, for "did you mean" in error messages.
#pragma once

#include <string>
#include <vector>

namespace evsim {

/// Levenshtein distance: insertions, deletions and substitutions.
size_t editDistance(const std::string& a, const std::string& b);

/// Up to `count` of `names` nearest to `name`, nearest first (ties in the
/// given order).
std::vector<std::string> nearestNames(const std::string& name,
                                      const std::vector<std::string>& names, size_t count);

}  // namespace evsim
