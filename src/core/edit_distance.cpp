// Edit distance between names, for "did you mean" in error messages. Declared
// and documented in endovascular_sim/core/edit_distance.h.
#include "endovascular_sim/core/edit_distance.h"

#include <algorithm>
#include <numeric>

namespace evsim {

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

std::vector<std::string> nearestNames(const std::string& name,
                                      const std::vector<std::string>& names, size_t count) {
  std::vector<size_t> order(names.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<size_t> distance(names.size());
  for (size_t i = 0; i < names.size(); ++i) distance[i] = editDistance(name, names[i]);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return distance[a] < distance[b]; });
  std::vector<std::string> out;
  for (size_t i = 0; i < std::min(count, order.size()); ++i) out.push_back(names[order[i]]);
  return out;
}

}  // namespace evsim
