// Detection of one step's contacts (the paper's section 3): the first root
// of the field along each sample point's path x_t -> x_f, the wall contacts
// kept from the last step, device pairs and lumen contacts; then, in each
// activation loop, the re-detection at the loop's x (plane updates, new
// contacts) and, once it converged, the tunnel check. Called by
// resolveContacts (contact_solver.cpp) through activation_loop.h.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "activation_loop.h"
#include "endovascular_sim/contact/coaxial.h"
#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/mechanics/so3.h"
#include "pair_detection.h"
#include "wall_planes.h"

namespace evsim::activation {

using fields::SampleFields;
using walls::depthOf;
using walls::farExit;
using walls::lastWallAlong;
using walls::tunnelExit;

void placeIterate(const ContactProblem& pb, LoopState* s) {
  const std::vector<DeviceState>& start = *pb.start;
  if (!s->held_placed) {
    s->x = start;
    for (size_t d = 0; d < s->x.size(); ++d) applyIncrement(s->dq[d], 0, &s->x[d]);
    s->held_placed = true;
  } else {
    // As applyIncrement from x_t, from the first free node on.
    for (size_t d = 0; d < s->x.size(); ++d) {
      const VecX& dq = s->dq[d];
      DeviceState& x = s->x[d];
      const int n = static_cast<int>(x.position.size());
      for (int i = std::max(0, (*pb.workspaces)[d].first_free_node); i < n; ++i) {
        x.position[i] = start[d].position[i] + dq.segment<3>(6 * i);
        x.rotation[i] = expQuaternion(dq.segment<3>(6 * i + 3)) * start[d].rotation[i];
        x.rotation[i].normalize();
      }
    }
  }
  s->at_x.reset(pb, &s->x);
}

/// True for a point of a detached part (a coil cut from its pusher): it has
/// left its outer device for good, so no lumen holds it.
bool detached(const DeviceState& x, const SamplePoint& s) {
  return x.cut_element >= 0 && s.element > x.cut_element;
}

/// Unit tangent of the device axis at a sample point.
Vec3 sampleTangent(const DeviceState& x, const SamplePoint& s) {
  const Vec3 t = (1.0 - s.xi) * (x.rotation[s.element] * Vec3::UnitX()) +
                 s.xi * (x.rotation[s.element + 1] * Vec3::UnitX());
  return t.normalized();
}

/// Outer device of device d (-1: none).
int outerOf(const ContactProblem& pb, size_t d) {
  return pb.outer_of && d < pb.outer_of->size() ? (*pb.outer_of)[d] : -1;
}

namespace {

/// A contact of the previous step that carried a force, or ended touching
/// (gap within `touching` [m]: a point resting with no force, which the
/// next step's free motion pushes through again).
bool carriedOrTouched(const Contact& prev, double touching) {
  return prev.force > 0.0 || std::abs(prev.gap) <= touching;
}

/// A wall contact of the previous step that starts this one
/// (carriedOrTouched), its point still taking part.
bool keptWallContact(const ContactProblem& pb, const Contact& prev, double touching) {
  if (prev.other_device >= 0 || prev.device >= static_cast<int>(pb.devices->size())) return false;
  if (!carriedOrTouched(prev, touching)) return false;
  return takesPart(pb, prev.device, (*pb.samples)[prev.device][prev.sample]);
}

bool hasKeptWallContacts(const ContactProblem& pb, double touching) {
  if (!pb.previous) return false;
  for (const Contact& prev : *pb.previous)
    if (keptWallContact(pb, prev, touching)) return true;
  return false;
}

/// Wall contacts that carried a force in the previous step start this one
/// (a pre-shaped tip held against the wall springs back out in the free
/// motion, and without its contact the first loops chase it millimetres
/// away), their planes where their points at x_t project on the wall.
void keepWallContacts(const ContactProblem& pb, const RootOptions& root, double touching,
                      SampleFields* field, SamplePositions* at_start,
                      std::vector<Contact>* contacts, std::vector<std::vector<int>>* contact_of) {
  if (!pb.previous || !pb.surface) return;
  for (const Contact& prev : *pb.previous) {
    if (!keptWallContact(pb, prev, touching)) continue;
    const int d = prev.device, k = prev.sample;
    if ((*contact_of)[d][k] >= 0) continue;
    const SamplePoint& s = (*pb.samples)[d][k];
    const Vec3& p0 = at_start->at(d, k);
    const SurfacePoint plane =
        projectToSurfaceFrom(*pb.surface, p0, field->start(d, k, p0, s.radius, pb.motion), s.radius,
                             pb.motion, 0.01, root);
    if (!plane.hit) continue;
    (*contact_of)[d][k] = static_cast<int>(contacts->size());
    Contact ct{d, k, plane.point, plane.normal, 0, 0};
    ct.force = prev.force;  // the friction solver's warm start
    ct.friction = prev.friction;
    contacts->push_back(ct);
  }
}

/// The deepest point beyond a wall or lumen over a pass [m], its device and
/// position (a point outside the field's support has an infinite depth).
struct DeepestPoint {
  double depth{0.0};
  int device{-1};
  Vec3 point{Vec3::Zero()};
  void offer(double d, int dev, const Vec3& p) {
    if (d <= depth) return;
    depth = d, device = dev, point = p;
  }
  void store(ContactStats* st) const {
    st->max_penetration_m = depth;
    st->deepest_device = device;
    st->deepest_point = point;
  }
};

/// Effect 'coaxial': a point of an inner device beyond its outer device's
/// lumen at x.
struct LumenViolation {
  int device, sample;
  LumenLocation location;
};

/// Points of inner devices beyond the lumen by more than `tolerance` at x,
/// per inner element and side the deepest only (two points are on one side
/// when their offsets across the lumen's axis lie within 90 degrees: a wire
/// bent in a curve presses one element on both sides). `at`: the points at x.
std::vector<LumenViolation> lumenViolations(const ContactProblem& pb,
                                            const std::vector<DeviceState>& x, SamplePositions* at,
                                            double tolerance) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  std::vector<LumenViolation> out;
  for (size_t d = 0; d < devices.size(); ++d) {
    const int outer = outerOf(pb, d);
    if (outer < 0) continue;
    int element = -1;
    size_t first_of_element = 0;  // the element's first entry in out
    OuterAxisCache outer_axis;
    const TakingPart taking = takingPart(pb, d);
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& s = samples[d][k];
      if (!taking(s) || detached(x[d], s)) continue;
      if (surelyWithinLumen(devices[d], x[d], s, devices[outer], x[outer], tolerance, &outer_axis,
                            &at->at(static_cast<int>(d), static_cast<int>(k))))
        continue;
      const LumenLocation loc = locateInLumen(devices[d], x[d], s, devices[outer], x[outer]);
      if (!loc.inside || loc.excess() <= tolerance) continue;
      const LumenViolation v{static_cast<int>(d), static_cast<int>(k), loc};
      if (s.element == element) {
        bool merged = false;  // into the entry of its side: across within 90 degrees
        for (size_t i = first_of_element; i < out.size() && !merged; ++i) {
          if (out[i].location.across.dot(loc.across) <= 0.0) continue;
          if (loc.excess() > out[i].location.excess()) out[i] = v;
          merged = true;
        }
        if (!merged) out.push_back(v);
        continue;
      }
      element = s.element;
      first_of_element = out.size();
      out.push_back(v);
    }
  }
  return out;
}

/// The lumen contact of a violation: the point against the lumen's tangent
/// plane where it lies.
Contact lumenContact(const LumenViolation& v, int outer) {
  Contact ct{v.device, v.sample, v.location.center, v.location.normal, 0, 0, outer, -1};
  ct.other = v.location.axis;
  ct.separation = -v.location.clearance;
  ct.lumen = true;
  return ct;
}

}  // namespace

/// The paper's detection on [x_t, x_f]: per element of each device, the
/// sample point deepest beyond the wall at x_f becomes a contact, its plane
/// at the first root of its path (the activation loop adds any other point
/// of the element that stays beyond). A path that ends inside but left the
/// lumen on the way (a corner cut through tissue) is a crossing too, at its
/// first root. Only the chosen point's root is searched: the depth at x_f
/// ranks the others for one evaluation each. Returns true when a point
/// beyond the wall has no plane (beyond every vessel's support: the step
/// cannot be solved).
bool detectWallCrossings(const ContactProblem& pb, const RootOptions& root, SampleFields* field,
                         LoopState* ls) {
  SamplePositions* at_start = &ls->at_start;
  SamplePositions* at_x = &ls->at_x;
  std::vector<Contact>* contacts = ls->contacts;
  std::vector<std::vector<int>>* contact_of = &ls->contact_of;
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  const ImplicitSurface& surface = *pb.surface;
  bool stranded = false;
  // The first root of sample k's path (g1: the field at its end, when
  // known), or its projection at x_f when it starts beyond the wall (within
  // the tolerance band, or a moving wall).
  auto crossing = [&](size_t d, int k, const Vec3& p0, const Vec3& p1, const FieldSample* g1) {
    const SamplePoint& s = samples[d][k];
    const FieldSample& g0 = field->start(d, k, p0, s.radius, pb.motion);
    SurfacePoint hit = g1 ? firstRootBetween(surface, p0, g0, p1, *g1, s.radius, pb.motion, root)
                          : firstRootFrom(surface, p0, g0, p1, s.radius, pb.motion, root);
    if (hit.hit && hit.started_outside) {
      hit = g1 ? projectToSurfaceFrom(surface, p1, *g1, s.radius, pb.motion, 0.01, root)
               : projectToSurface(surface, p1, s.radius, pb.motion, 0.01, root);
      if (!hit.hit) stranded = true;  // beyond every vessel's support: no plane
    }
    return hit;
  };
  for (size_t d = 0; d < devices.size(); ++d) {
    struct Best {
      int sample{-1};
      double depth{-1.0};
      SurfacePoint hit;  // (not yet searched when !hit.hit)
    } best;
    int element = -1;
    const TakingPart taking = takingPart(pb, d);
    auto flush = [&]() {
      if (best.sample < 0) return;
      if (!best.hit.hit)
        best.hit = crossing(d, best.sample, at_start->at(d, best.sample), at_x->at(d, best.sample),
                            nullptr);
      if (best.hit.hit) {
        (*contact_of)[d][best.sample] = static_cast<int>(contacts->size());
        contacts->push_back(
            {static_cast<int>(d), best.sample, best.hit.point, best.hit.normal, 0, 0});
      }
      best = Best{};
    };
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& s = samples[d][k];
      if (s.element != element) {
        flush();
        element = s.element;
      }
      if (!taking(s)) continue;
      const Vec3& p0 = at_start->at(d, k);
      const Vec3& p1 = at_x->at(d, k);
      if (field->startInside(d, k, p0, p1, s.radius, pb.motion)) continue;
      if ((*contact_of)[d][k] >= 0) continue;  // a contact already (kept from the last step)
      const FieldSample& g1 = field->end(d, k, p1, s.radius, pb.motion);
      if (g1.value < 0.0) {  // beyond at x_f: ranked by its depth, searched if deepest
        const double depth = depthOf(g1);
        if (depth > best.depth) best = {static_cast<int>(k), depth, SurfacePoint{}};
        continue;
      }
      const SurfacePoint hit = crossing(d, k, p0, p1, &g1);
      if (!hit.hit) continue;
      const double depth = -hit.normal.dot(p1 - hit.point);
      if (depth > best.depth) best = {static_cast<int>(k), depth, hit};
    }
    flush();
  }
  return stranded;
}

namespace {

void addLumen(const ContactProblem& pb, const LumenViolation& v, LoopState* s) {
  s->lumen_of[v.device][v.sample] = static_cast<int>(s->contacts->size());
  s->contacts->push_back(lumenContact(v, outerOf(pb, v.device)));
}

/// A lumen contact of the previous step that starts this one
/// (carriedOrTouched), its inner device still in the same outer device.
bool keptLumenContact(const ContactProblem& pb, const Contact& prev, double touching) {
  if (!prev.lumen || prev.device >= static_cast<int>(pb.devices->size())) return false;
  if (!carriedOrTouched(prev, touching)) return false;
  return outerOf(pb, prev.device) == prev.other_device;
}

/// Effect 'coaxial': the lumen contacts of the previous step that carried a
/// force or touched, their planes where their points lie at x_t (like the
/// wall's, below); without such contacts, the inner devices' points beyond
/// their outer device's lumen at x_f (per inner element the deepest).
/// Points beyond the lumen later are found by the loop's passes at x. Why
/// not at x_f when contacts are kept: a wire held bent in a pre-shaped
/// catheter springs millimetres across the lumen in the free motion, and
/// planes taken there, far from where the loop ends, are dozens of rows that
/// hold nothing (arch_navigation_headhunter at rest: 147 rows and 10 loops a
/// step, against 11 rows asleep).
void detectLumenContacts(const ContactProblem& pb, double touching, LoopState* s) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  const auto& start = *pb.start;
  bool kept = false;
  if (pb.previous) {
    for (const Contact& prev : *pb.previous) {
      if (!keptLumenContact(pb, prev, touching)) continue;
      const int d = prev.device, k = prev.sample, outer = prev.other_device;
      const SamplePoint& sp = samples[d][k];
      if (s->lumenContactOf(d, k) >= 0 || !takesPart(pb, d, sp) || detached(start[d], sp)) continue;
      const LumenViolation v{d, k,
                             locateInLumen(devices[d], start[d], sp, devices[outer], start[outer])};
      if (!v.location.inside || v.location.across.norm() == 0.0) continue;
      addLumen(pb, v, s);
      s->contacts->back().force = prev.force;  // the friction solver's warm start
      s->contacts->back().friction = prev.friction;
      kept = true;
    }
  }
  if (kept) return;
  for (const LumenViolation& v : lumenViolations(pb, s->x, &s->at_x, 0.0)) addLumen(pb, v, s);
}

/// The plane for a point of device d, sample k, found beyond the wall at p
/// (its path from p0 = its position at x_t; g the field at p): where p
/// projects; beyond every vessel's support (a flat field, no projection),
/// where the path crossed the wall.
SurfacePoint planeForViolation(const ContactProblem& pb, const RootOptions& root,
                               const SamplePoint& sp, const Vec3& p0, const Vec3& p,
                               const FieldSample& g) {
  SurfacePoint plane = projectToSurfaceFrom(*pb.surface, p, g, sp.radius, pb.motion, 0.01, root);
  if (plane.hit) return plane;
  // No projection (beyond every vessel's support the field is flat):
  // the wall where the point's path from x_t crossed it.
  const SurfacePoint hit = firstRoot(*pb.surface, p0, p, sp.radius, pb.motion, root);
  if (hit.hit && !hit.started_outside) plane = hit;
  // At x_t already within the tolerance band beyond the wall: where
  // the path, having crossed the lumen, leaves it through the far
  // wall; if it never enters the lumen, the wall nearest to where it
  // left the support (the point slid along its plane, millimetres
  // round a bend). The plane where it was would hold nothing: the
  // point satisfies it, and it was added again in every loop.
  if (hit.started_outside) {
    plane = farExit(*pb.surface, p0, p, sp.radius, pb.motion, root);
    if (!plane.hit) plane = lastWallAlong(*pb.surface, p0, p, sp.radius, pb.motion, root);
  }
  return plane;
}

/// The wall's part of the re-detection: every point at x beyond the wall by
/// more than the tolerance updates its contact's plane (once a step) or
/// gets a new one. Returns false when a point is violated; *deepest: the
/// deepest point.
bool redetectWalls(const ContactProblem& pb, const ContactOptions& o, SampleFields* field,
                   int fresh_from, LoopState* s, DeepestPoint* deepest) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  const RootOptions& root = o.root;
  bool solved = true;
  for (size_t d = 0; d < devices.size(); ++d) {
    const TakingPart taking = takingPart(pb, d);
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& sp = samples[d][k];
      if (!taking(sp)) continue;
      const Vec3& p = s->at_x.at(d, k);
      double depth_bound = 0.0;
      if (field->endWithinTolerance(d, k, p, sp.radius, pb.motion, o.penetration_tolerance,
                                    &depth_bound)) {
        deepest->offer(depth_bound, static_cast<int>(d), p);
        continue;
      }
      const FieldSample& g = field->end(d, k, p, sp.radius, pb.motion);
      deepest->offer(depthOf(g), static_cast<int>(d), p);
      if (depthOf(g) <= o.penetration_tolerance) continue;
      solved = false;
      if (s->contact_of[d][k] >= fresh_from) continue;  // just detected: solved first
      const Vec3& p0 = s->at_start.at(d, k);
      SurfacePoint plane = planeForViolation(pb, root, sp, p0, p, g);
      const int existing = s->contact_of[d][k];
      if (existing >= 0 && !s->updated[existing]) {
        // The paper's update: the tangent plane where x projects.
        if (!plane.hit) continue;
        Contact& ct = (*s->contacts)[existing];
        ct.point = plane.point;
        ct.normal = plane.normal;
        s->updated[existing] = 1;
        continue;
      }
      if (existing < 0) {
        SurfacePoint hit =
            firstRootFrom(*pb.surface, p0, field->start(d, k, p0, sp.radius, pb.motion), p,
                          sp.radius, pb.motion, root);
        if (hit.hit && !hit.started_outside) plane = hit;
      }
      // A new contact, or a second plane for a point violated again after
      // its update (a concave wall: updates alone can oscillate; the extra
      // plane only shrinks the admissible set, so the loop converges).
      if (!plane.hit) continue;
      s->contact_of[d][k] = static_cast<int>(s->contacts->size());
      s->contacts->push_back(
          {static_cast<int>(d), static_cast<int>(k), plane.point, plane.normal, 0, 0});
      s->updated.push_back(0);
    }
  }
  return solved;
}

/// Like wall contacts: a point still beyond the lumen (by more than
/// options.lumen_tolerance) has its contact moved to the tangent plane
/// where it now lies, once; beyond it again, it gets a second plane (updates alone converge slowly:
/// measured on carotid_catheter, nearly every step needed halving). Only the deepest point per
/// inner element and side gets a plane in a pass, as at x_f: a wire lying along the lumen has every
/// sample of an element a little beyond, and one plane per element holds it (all of them: 60 % more
/// rows and 1.4x the step time on arch_to_right_subclavian). Returns false when a point is beyond;
/// *deepest grows to its excess [m].
bool redetectLumen(const ContactProblem& pb, const ContactOptions& o, LoopState* s,
                   DeepestPoint* deepest) {
  bool solved = true;
  for (const LumenViolation& v : lumenViolations(pb, s->x, &s->at_x, o.lumen_tolerance)) {
    solved = false;
    deepest->offer(v.location.excess(), v.device, s->at_x.at(v.device, v.sample));
    const int existing = s->lumenContactOf(v.device, v.sample);
    if (existing >= 0 && !s->updated[existing]) {
      const Contact fresh = lumenContact(v, outerOf(pb, v.device));
      Contact& ct = (*s->contacts)[existing];
      ct.point = fresh.point;
      ct.normal = fresh.normal;
      ct.other = fresh.other;
      ct.separation = fresh.separation;
      s->updated[existing] = 1;
    } else {
      addLumen(pb, v, s);
      s->updated.push_back(0);
    }
  }
  return solved;
}

/// The largest gap [m] at which a wall contact of the last step without
/// force starts this one (options.keep_gap): a point that lifted off its
/// plane by a few micrometres as a moving wall drew back crosses the wall
/// again when it returns, and found only at the first iterate it costs a
/// second loop.
double keptWithin(const ContactOptions& o) { return std::max(o.penetration_tolerance, o.keep_gap); }

}  // namespace

bool detectOnFreeMotion(const ContactProblem& pb, const ContactOptions& o, SampleFields* field,
                        LoopState* s, bool* detect_later, ContactStats* st) {
  const RootOptions& root = o.root;
  // With wall contacts kept from the last step, the paper's detection runs
  // on the path to the first loop's iterate instead of the free motion's:
  // a device held by its contacts swings millimetres away from them in the
  // free motion, and crossings along that path are undone by the kept
  // contacts in the first loop anyway (options.detect_on_first_iterate).
  *detect_later = o.detect_on_first_iterate && pb.surface && hasKeptWallContacts(pb, keptWithin(o));
  // A point beyond the wall where no plane can be found.
  bool stranded = pb.surface && !*detect_later && detectWallCrossings(pb, root, field, s);
  keepWallContacts(pb, root, keptWithin(o), field, &s->at_start, s->contacts, &s->contact_of);
  if (*detect_later && s->contacts->empty()) {  // no kept contact found its plane
    *detect_later = false;
    stranded = detectWallCrossings(pb, root, field, s);
  }
  // Device points closer than the sum of their radii at x_f (element pairs
  // that crossed on the way there held from where they first touched), or
  // only those overlapping by more than new_pair_overlap: at a predicted
  // first iterate a packed coil's turns all touch, within the pair
  // tolerance, where the last step's forces held them, and the pairs among
  // them that held no force (two in three) would be rows the loop never
  // needs; a pair pressed deeper than the tolerance is added by the loop.
  // Element pairs that passed through each other in the free motion are
  // looked for here only when no contact calls for the loop; otherwise in
  // the loop's iterates, where they still pass: a packed coil's free motion,
  // springing open, carries its turns by up to millimetres through each
  // other, and the first loop's contacts undo most of those passes.
  if (pb.effects.device_contact) {
    const auto tp = Clock::now();
    const int kept_from = static_cast<int>(s->contacts->size());
    keepPairs(pb, o.element_pairs, s);
    const std::array<int, 2> kept{kept_from, static_cast<int>(s->contacts->size())};
    const bool passed_through = s->contacts->empty();
    for (const FoundPair& f :
         devicePairs(pb, o.element_pairs, s->x, -o.new_pair_overlap, stepStartAxes(pb, o, s),
                     passed_through, true, &s->at_x)) {
      if (s->pair_contact.count(f.key)) continue;
      addPair(f, s);
      if (o.element_pairs && o.slid_pair_warm_start)
        st->slid_forces += takeOverSlidForce(f, kept, s);
    }
    ++st->pair_passes;
    st->times.device_contact_ms += msSince(tp);
  }
  if (pb.outer_of && !pb.outer_of->empty()) {  // effect 'coaxial'
    const auto tl = Clock::now();
    detectLumenContacts(pb, o.penetration_tolerance, s);
    ++st->lumen_passes;
    st->times.coaxial_ms += msSince(tl);
  }
  return stranded;
}

bool redetect(const ContactProblem& pb, const ContactOptions& o, SampleFields* field,
              int fresh_from, LoopState* s, ContactStats* st) {
  DeepestPoint deepest;  // over all points at x: the step's penetration if this is the last loop
  bool solved = true;
  if (pb.surface) solved = redetectWalls(pb, o, field, fresh_from, s, &deepest);
  deepest.store(st);
  if (pb.effects.device_contact) {
    const auto tp = Clock::now();
    ++st->pair_passes;
    solved = redetectPairs(pb, o, s) && solved;
    st->times.device_contact_ms += msSince(tp);
  }
  if (pb.outer_of && !pb.outer_of->empty()) {  // effect 'coaxial'
    const auto tl = Clock::now();
    ++st->lumen_passes;
    solved = redetectLumen(pb, o, s, &deepest) && solved;
    deepest.store(st);
    st->times.coaxial_ms += msSince(tl);
  }
  return solved;
}

bool checkTunnels(const ContactProblem& pb, const ContactOptions& o, SampleFields* field,
                  LoopState* s, ContactStats* st) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  bool none = true;
  for (size_t d = 0; d < devices.size() && pb.surface; ++d) {
    const TakingPart taking = takingPart(pb, d);
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& sp = samples[d][k];
      if (!taking(sp)) continue;
      const Vec3& p0 = s->at_start.at(d, k);
      const Vec3& p = s->at_x.at(d, k);
      if (field->chordInside(d, k, p0, p)) continue;
      const SurfacePoint exit =
          tunnelExit(*pb.surface, p0, field->start(d, k, p0, sp.radius, pb.motion), p,
                     field->end(d, k, p, sp.radius, pb.motion), sp.radius, pb.motion, o.root);
      if (!exit.hit) continue;
      ++st->tunnels;
      none = false;
      s->contact_of[d][k] = static_cast<int>(s->contacts->size());
      s->contacts->push_back(
          {static_cast<int>(d), static_cast<int>(k), exit.point, exit.normal, 0, 0});
      s->updated.push_back(0);
    }
  }
  return none;
}

}  // namespace evsim::activation
