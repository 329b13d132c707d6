// Iodinated contrast in the vessels: an injection fills the vessel tree
// downstream of a point (the catheter's tip) for a while, then washes out.
// Declared and documented in endovascular_sim/imaging/contrast.h.
#include "endovascular_sim/imaging/contrast.h"

#include <algorithm>
#include <limits>

namespace evsim {

ContrastAgent::ContrastAgent(std::shared_ptr<const Centerline> centerline)
    : centerline_(std::move(centerline)) {
  if (!centerline_) return;
  children_.resize(centerline_->numPoints());
  for (int i = 0; i < centerline_->numPoints(); ++i)
    if (centerline_->parent[i] >= 0) children_[centerline_->parent[i]].push_back(i);
}

int ContrastAgent::nearestSegment(const Vec3& p) const {
  if (!centerline_) return -1;
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < centerline_->numPoints(); ++i) {
    const int parent = centerline_->parent[i];
    if (parent < 0) continue;
    const Vec3& a = centerline_->position[parent];
    const Vec3 ab = centerline_->position[i] - a;
    const double s = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-30), 0.0, 1.0);
    const double d = (a + s * ab - p).norm() / std::max(centerline_->radius[i], 1e-9);
    if (d < best_distance) best_distance = d, best = i;
  }
  return best;
}

std::vector<int> ContrastAgent::downstream(int point) const {
  std::vector<int> below;
  if (point < 0) return below;
  std::vector<int> stack{point};
  while (!stack.empty()) {
    const int k = stack.back();
    stack.pop_back();
    below.push_back(k);
    for (int c : children_[k]) stack.push_back(c);
  }
  return below;
}

int ContrastAgent::inject(const Vec3& at, double start, double duration, double concentration,
                          double washout) {
  const int first = nearestSegment(at);
  if (first < 0) return 0;
  Injection j;
  j.filled.assign(centerline_->numPoints(), 0);
  const std::vector<int> below = downstream(first);
  for (int k : below) j.filled[k] = 1;
  j.start = start;
  j.duration = duration;
  j.concentration = concentration;
  j.washout = washout;
  injections_.push_back(std::move(j));
  return static_cast<int>(below.size());
}

double ContrastAgent::level(const Injection& j, double t) {
  if (t < j.start) return 0.0;
  const double end = j.start + j.duration;
  if (t <= end) return j.concentration;
  return j.concentration * std::max(0.0, 1.0 - (t - end) / j.washout);
}

double ContrastAgent::concentration(int point, double t) const {
  double c = 0.0;
  for (const Injection& j : injections_)
    if (j.filled[point]) c = std::max(c, level(j, t));
  return c;
}

bool ContrastAgent::active(double t) const {
  return std::any_of(injections_.begin(), injections_.end(),
                     [&](const Injection& j) { return level(j, t) > 0.0; });
}

}  // namespace evsim
