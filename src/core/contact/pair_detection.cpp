// Device pairs as contacts (the effect 'device_contact'). Declared and
// documented in pair_detection.h.
#include "pair_detection.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <map>

#include "contact_workspace_kept.h"
#include "device_pairs.h"
#include "endovascular_sim/contact/coaxial.h"

namespace evsim::activation {

using pairs::ElementRef;
using pairs::Pair;
using pairs::pairNormal;
using pairs::PointRef;

namespace {

/// Half the stretch of its device's axis that sample point k stands for
/// [m]: half its mean distance to its neighbours along the device.
double sampleReach(const ContactProblem& pb, int d, int k) {
  const DeviceModel& model = (*pb.devices)[d];
  const std::vector<SamplePoint>& samples = (*pb.samples)[d];
  const int lo = std::max(0, k - 1), hi = std::min(k + 1, static_cast<int>(samples.size()) - 1);
  if (hi <= lo) return 0.0;
  return 0.5 * (materialCoordinate(model, samples[hi]) - materialCoordinate(model, samples[lo])) /
         (hi - lo);
}

/// The normal of a pair of sample points (device da's sample ka at pa,
/// db's kb at pb) in configuration x: between the closest points of the
/// stretches they stand for (pairs::pairNormal).
Vec3 samplePairNormal(const ContactProblem& pb, const std::vector<DeviceState>& x, int da, int ka,
                      const Vec3& pa, int db, int kb, const Vec3& pb_) {
  const auto& samples = *pb.samples;
  return pairNormal(pa, sampleTangent(x[da], samples[da][ka]), pb_,
                    sampleTangent(x[db], samples[db][kb]), sampleReach(pb, da, ka),
                    sampleReach(pb, db, kb));
}

/// Sample points of all devices at x that may pair: every free one, and the
/// held ones within reach of a free one. A point of an inner device within
/// its outer device's lumen, or less than a few radii beyond its tip, is marked:
/// it touches the outer device through the lumen constraint, never as a pair.
/// positions: the points at x, when the pass has them (else computed here).
std::vector<PointRef> freePoints(const ContactProblem& pb, const std::vector<DeviceState>& x,
                                 SamplePositions* positions) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  // A pair needs a free point, and its points closer than their radii: a
  // held point beyond the free points' box grown by twice the largest
  // radius pairs with none (most of a device still in its introducer), and
  // neither does a held element's point when the element's box (its nodes',
  // grown by half its length: more than any bow) misses it.
  auto position = [&](size_t d, size_t k) {
    return positions ? positions->at(d, k) : samplePosition(devices[d], x[d], samples[d][k]);
  };
  Eigen::AlignedBox3d box;
  double rmax = 0.0;
  std::vector<std::vector<char>> free(devices.size());  // per sample: takes part
  std::vector<std::vector<Vec3>> at(devices.size());    // per free sample: its position
  for (size_t d = 0; d < devices.size(); ++d) {
    free[d].resize(samples[d].size());
    at[d].resize(samples[d].size());
    const TakingPart taking = takingPart(pb, d);
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& sp = samples[d][k];
      rmax = std::max(rmax, sp.radius);
      free[d][k] = taking(sp);
      if (!free[d][k] || (sp.element == x[d].cut_element && sp.xi > 0.0)) continue;
      at[d][k] = position(d, k);
      box.extend(at[d][k]);
    }
  }
  if (box.isEmpty()) return {};
  box.min().array() -= 2.0 * rmax;
  box.max().array() += 2.0 * rmax;
  auto elementMisses = [&](size_t d, int e) {
    Eigen::AlignedBox3d span(x[d].position[e]);
    span.extend(x[d].position[e + 1]);
    span.min().array() -= 0.5 * devices[d].elements[e].length;
    span.max().array() += 0.5 * devices[d].elements[e].length;
    return !box.intersects(span);
  };
  std::vector<PointRef> pts;
  size_t count = 0;
  for (const auto& on_device : samples) count += on_device.size();
  pts.reserve(count);
  for (size_t d = 0; d < devices.size(); ++d) {
    const int outer = outerOf(pb, d);
    const double reach = outer < 0
                             ? 0.0
                             : x[outer].inserted_length + 4.0 * devices[outer].node_radius.back() +
                                   devices[outer].elements.back().length;
    int missed = -1;  // the last held element found out of reach
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& sp = samples[d][k];
      if (sp.element == x[d].cut_element && sp.xi > 0.0) continue;  // the detachment's gap
      const bool part = free[d][k] != 0;
      if (!part && (sp.element == missed || elementMisses(d, sp.element))) {
        missed = sp.element;
        continue;
      }
      const Vec3 p = part ? at[d][k] : position(d, k);
      if (!part && !box.contains(p)) continue;
      const double s = materialCoordinate(devices[d], sp);
      const bool held =
          outer >= 0 && !detached(x[d], sp) && pathLength(devices[d], x[d], s) < reach;
      pts.push_back({part, static_cast<int>(d), static_cast<int>(k), sp.element, s, p, sp.radius,
                     held ? outer : -1, detached(x[d], sp) ? 1 : 0});
    }
  }
  return pts;
}

/// The elements of all devices at x that may pair: every one with a free
/// node, and the held ones within reach of a free one. An element of an
/// inner device within its outer device's lumen, or less than a few radii
/// beyond its tip, is marked: it touches the outer device through the lumen
/// constraint, never as a pair. The element cut by a detachment is none.
/// Given the axes at the step's start `from`, each element's box holds its
/// axis there too, and its sweep bounds how far its axis points moved
/// (device_pairs.h).
std::vector<ElementRef> pairElements(const ContactProblem& pb, const std::vector<DeviceState>& x,
                                     const pairs::StartAxes* from) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  // A pair needs a free element: a held one whose box misses the free
  // ones' box pairs with none (most of a device still in its introducer).
  // Given the step's start: the box holds the axis all along the step, and
  // how far it moved.
  auto addMotion = [&](ElementRef* el) {
    const int d = el->device, e = el->element;
    const HermiteAxis& start = from->axis(d, e);
    const double bow_from = from->bow(d, e);
    Eigen::AlignedBox3d was(start.p0);
    was.extend(start.p1);
    was.min().array() -= el->point.radius + bow_from;
    was.max().array() += el->point.radius + bow_from;
    el->box.extend(was);
    const HermiteAxis moved{el->axis.p0 - start.p0, el->axis.p1 - start.p1, el->axis.m0 - start.m0,
                            el->axis.m1 - start.m1};
    const double moved_bow = moved.bow();
    el->sweep = std::max(moved.p0.norm(), moved.p1.norm()) + moved_bow;
    el->shift = moved.p0;
    el->spread = (moved.p1 - moved.p0).norm() + moved_bow;
  };
  std::vector<ElementRef> els;
  size_t total = 0;
  for (const DeviceModel& m : devices) total += m.elements.size();
  els.reserve(total);
  Eigen::AlignedBox3d reach_of_free;
  for (size_t d = 0; d < devices.size(); ++d) {
    const DeviceModel& m = devices[d];
    const int first_free = (*pb.workspaces)[d].first_free_node;
    const int outer = outerOf(pb, d);
    const double reach = outer < 0
                             ? 0.0
                             : x[outer].inserted_length + 4.0 * devices[outer].node_radius.back() +
                                   devices[outer].elements.back().length;
    // Each node's tangent once (two elements share it): the axes' bows.
    std::vector<Vec3> tangent(x[d].position.size());
    for (size_t i = 0; i < tangent.size(); ++i) tangent[i] = x[d].rotation[i] * Vec3::UnitX();
    int e = -1;
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& sp = samples[d][k];
      if (sp.element == e || sp.xi == 1.0) continue;  // its first sample only
      e = sp.element;
      if (e == x[d].cut_element) continue;
      ElementRef el{e + 1 >= first_free,
                    static_cast<int>(d),
                    e,
                    detached(x[d], sp) ? 1 : 0,
                    -1,
                    static_cast<int>(k),
                    sp,
                    Eigen::AlignedBox3d(x[d].position[e])};
      const double L = m.elements[e].length;
      el.axis = {x[d].position[e], x[d].position[e + 1], L * tangent[e], L * tangent[e + 1]};
      el.bow = el.axis.bow();
      el.box.extend(x[d].position[e + 1]);
      el.box.min().array() -= sp.radius + el.bow;
      el.box.max().array() += sp.radius + el.bow;
      if (from && el.free) addMotion(&el);
      const double s = m.node_s[e];
      if (outer >= 0 && !detached(x[d], sp) && pathLength(m, x[d], s) < reach)
        el.in_lumen_of = outer;
      if (el.free) reach_of_free.extend(el.box);
      els.push_back(el);
    }
  }
  if (reach_of_free.isEmpty()) return {};
  els.erase(std::remove_if(els.begin(), els.end(),
                           [&](const ElementRef& el) {
                             return !el.free && !reach_of_free.intersects(el.box);
                           }),
            els.end());
  if (from)
    for (ElementRef& el : els)
      if (!el.free) addMotion(&el);
  return els;
}

/// The sample points' pair candidates, kept from pass to pass and from
/// step to step in the simulation's contact workspace (nullptr without
/// one): a coil's points move some micrometres a step, and the candidates
/// stay valid for several steps. Whatever built them, they are used only
/// where every point of the pass was there with its radius and moved less
/// than the skin since (findPointPairs): the pairs found are those of a
/// full search.
pairs::PointCandidates* keptPointCandidates(const ContactProblem& pb) {
  return pb.kept ? &pb.kept->kept().point_candidates : nullptr;
}

/// The element pairs' candidates, kept the same way: used only where every
/// element of the pass was there, free or held as now, and its box stays
/// within its box there grown by the skin (findPairs): the pairs found are
/// those of a full search.
pairs::PairCandidates* keptElementCandidates(const ContactProblem& pb) {
  return pb.kept ? &pb.kept->kept().element_candidates : nullptr;
}

}  // namespace

/// The device pairs at x within `margin` [m]: sample points closer than
/// the sum of their radii, their normal across both local axes; or
/// (contact.element_pairs) elements whose axes come that close, at the
/// axes' closest points, the normal from one to the other (across both
/// local axes where they meet).
std::vector<FoundPair> devicePairs(const ContactProblem& pb, bool element_pairs,
                                   const std::vector<DeviceState>& x, double margin,
                                   const pairs::StartAxes* from, bool passed_through,
                                   bool keep_candidates, SamplePositions* positions) {
  const auto& samples = *pb.samples;
  std::vector<FoundPair> out;
  auto found = [&](int da, int sa, int ea, int db, int sb, int eb) {
    FoundPair f;
    f.device_a = da, f.sample_a = sa, f.element_a = ea;
    f.device_b = db, f.sample_b = sb, f.element_b = eb;
    return f;
  };
  if (!element_pairs) {
    const std::vector<PointRef> pts = freePoints(pb, x, positions);
    for (const pairs::PointPair& pr : pairs::findPointPairs(
             *pb.devices, pts, margin, keep_candidates ? keptPointCandidates(pb) : nullptr)) {
      const PointRef &a = pts[pr.a], &b = pts[pr.b];
      FoundPair f = found(a.device, a.sample, a.element, b.device, b.sample, b.element);
      f.key = {a.device, a.sample, b.device, b.sample};
      f.on_a = samples[a.device][a.sample];
      f.on_b = samples[b.device][b.sample];
      f.at_b = b.p;
      f.normal = samplePairNormal(pb, x, a.device, a.sample, a.p, b.device, b.sample, b.p);
      f.depth = a.r + b.r - pr.distance;
      out.push_back(f);
    }
    return out;
  }
  const std::vector<ElementRef> els = pairElements(pb, x, from);
  for (const Pair& pr : pairs::findPairs(*pb.devices, x, els, margin, from, passed_through,
                                         keep_candidates ? keptElementCandidates(pb) : nullptr)) {
    const ElementRef &a = els[pr.a], &b = els[pr.b];
    FoundPair f = found(a.device, a.sample, a.element, b.device, b.sample, b.element);
    f.key = {a.device, a.element, b.device, b.element};
    f.on_a = pr.on_a;
    f.on_b = pr.on_b;
    f.at_b = pr.pb;
    const double radii = pr.on_a.radius + pr.on_b.radius;
    f.normal = pr.swept ? pr.normal
               : pr.distance > 1e-6 * radii
                   ? Vec3((pr.pa - pr.pb) / pr.distance)
                   : pairNormal(pr.pa, sampleTangent(x[a.device], pr.on_a), pr.pb,
                                sampleTangent(x[b.device], pr.on_b));
    f.depth = radii - pr.distance;
    out.push_back(f);
  }
  return out;
}

void keepPairs(const ContactProblem& pb, bool element_pairs, LoopState* s) {
  if (!pb.previous) return;
  const auto& devices = *pb.devices;
  const auto& start = *pb.start;
  for (const Contact& prev : *pb.previous) {
    if (prev.other_device < 0 || prev.lumen || !(prev.force > 0.0)) continue;
    const int da = prev.device, db = prev.other_device;
    if (prev.self.element == start[da].cut_element || prev.other.element == start[db].cut_element)
      continue;  // (detached since)
    const auto& ws = *pb.workspaces;
    if (prev.self.element + 1 < ws[da].first_free_node &&
        prev.other.element + 1 < ws[db].first_free_node)
      continue;  // (both withdrawn into their introducers since: no free node)
    if (!element_pairs && prev.other_sample < 0) continue;  // (no second sample: none to keep)
    // Keyed as devicePairs finds it again: by elements, or by sample points.
    const std::array<int, 4> key =
        element_pairs ? std::array<int, 4>{da, prev.self.element, db, prev.other.element}
                      : std::array<int, 4>{da, prev.sample, db, prev.other_sample};
    if (s->pair_contact.count(key)) continue;
    const double near = prev.separation + std::max(prev.self.radius, prev.other.radius);
    if ((samplePosition(devices[da], s->x[da], prev.self) -
         samplePosition(devices[db], s->x[db], prev.other))
            .squaredNorm() > near * near)
      continue;  // carried apart in the first iterate
    const Vec3 pa = samplePosition(devices[da], start[da], prev.self);
    const Vec3 pb_ = samplePosition(devices[db], start[db], prev.other);
    Contact ct = prev;  // its points, and its force as the warm start
    ct.point = pb_;
    if (!element_pairs)  // as devicePairs makes it
      ct.normal = samplePairNormal(pb, start, da, prev.sample, pa, db, prev.other_sample, pb_);
    else if ((pa - pb_).norm() > 1e-6 * prev.separation)
      ct.normal = (pa - pb_).normalized();
    ct.gap = 0.0;
    s->pair_contact[key] = static_cast<int>(s->contacts->size());
    s->contacts->push_back(ct);
  }
}

void addPair(const FoundPair& f, LoopState* s) {
  s->pair_contact[f.key] = static_cast<int>(s->contacts->size());
  Contact ct{f.device_a, f.sample_a, f.at_b, f.normal, 0, 0, f.device_b, f.sample_b};
  ct.self = f.on_a;
  ct.other = f.on_b;
  ct.separation = f.on_a.radius + f.on_b.radius;
  s->contacts->push_back(ct);
}

bool takeOverSlidForce(const FoundPair& f, std::array<int, 2> kept, LoopState* s) {
  // One element along one axis first, then along both.
  constexpr int kAlong[8][2] = {{-1, 0},  {1, 0}, {0, -1}, {0, 1},
                                {-1, -1}, {1, 1}, {-1, 1}, {1, -1}};
  Contact& taker = (*s->contacts)[s->pair_contact.at(f.key)];
  for (const auto& step : kAlong) {
    const auto it =
        s->pair_contact.find({f.key[0], f.key[1] + step[0], f.key[2], f.key[3] + step[1]});
    if (it == s->pair_contact.end() || it->second < kept[0] || it->second >= kept[1]) continue;
    Contact& left = (*s->contacts)[it->second];
    if (!(left.force > 0.0)) continue;
    taker.force = left.force;
    taker.friction = left.friction;  // (the friction solver's warm start)
    left.force = 0.0;
    left.friction.setZero();
    return true;
  }
  return false;
}

const pairs::StartAxes* stepStartAxes(const ContactProblem& pb, const ContactOptions& o,
                                      LoopState* s) {
  if (!o.element_pairs) return nullptr;
  if (!s->start_axes) s->start_axes = std::make_unique<pairs::StartAxes>(*pb.devices, *pb.start);
  return s->start_axes.get();
}

bool redetectPairs(const ContactProblem& pb, const ContactOptions& o, LoopState* s) {
  bool solved = true;
  const double tolerance = std::max(o.penetration_tolerance, o.pair_tolerance);
  for (const FoundPair& f : devicePairs(pb, o.element_pairs, s->x, -tolerance,
                                        stepStartAxes(pb, o, s), true, true, &s->at_x)) {
    solved = false;
    const auto it = s->pair_contact.find(f.key);
    if (it != s->pair_contact.end() && !s->updated[it->second]) {
      Contact& ct = (*s->contacts)[it->second];  // the pair at x
      ct.normal = f.normal;
      ct.point = f.at_b;
      ct.self = f.on_a;
      ct.other = f.on_b;
      s->updated[it->second] = 1;
    } else {
      addPair(f, s);
      s->updated.push_back(0);
    }
  }
  return solved;
}

}  // namespace evsim::activation

namespace evsim {

std::vector<DeviceOverlap> deviceOverlaps(const ContactProblem& pb, double tolerance,
                                          bool element_pairs) {
  std::map<std::array<int, 4>, double> deepest;  // (device, element, device, element) -> depth
  for (const activation::FoundPair& f :
       activation::devicePairs(pb, element_pairs, *pb.start, -tolerance)) {
    double& depth = deepest[{f.device_a, f.element_a, f.device_b, f.element_b}];
    depth = std::max(depth, f.depth);
  }
  std::vector<DeviceOverlap> out;
  for (const auto& [key, depth] : deepest) out.push_back({key[0], key[1], key[2], key[3], depth});
  std::sort(out.begin(), out.end(),
            [](const DeviceOverlap& x, const DeviceOverlap& y) { return x.depth > y.depth; });
  return out;
}

}  // namespace evsim
