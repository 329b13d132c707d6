#include "endovascular_sim/contact/contact_solver.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "device_pairs.h"
#include "endovascular_sim/contact/coaxial.h"
#include "endovascular_sim/contact/delassus.h"
#include "endovascular_sim/contact/wall_curvature.h"
#include "endovascular_sim/mechanics/elasticity.h"
#include "sample_fields.h"
#include "wall_planes.h"

namespace evsim {
namespace {

using fields::SampleFields;
using pairs::findPairs;
using pairs::Pair;
using pairs::pairNormal;
using pairs::PointRef;
using walls::depthOf;
using walls::farExit;
using walls::lastWallAlong;
using walls::tunnelExit;
using Clock = std::chrono::steady_clock;

/// Rows of one device from which W comes from the band of A^-1 (one O(n)
/// selected inversion per matrix, then the sweep) rather than from the
/// block solve Y = A^-1 H^T (O(c n) triangular solves): the two cost the
/// same at about 16 rows on a 200-element wire (BM_Delassus*).
constexpr int kChainDelassusMinRows = 16;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Configuration x_t (+) dq for every device.
std::vector<DeviceState> moved(const std::vector<DeviceState>& start, const std::vector<VecX>& dq) {
  std::vector<DeviceState> x = start;
  for (size_t d = 0; d < x.size(); ++d) applyIncrement(dq[d], 0, &x[d]);
  return x;
}

/// True when the sample point moves with at least one free node.
bool isFree(const SamplePoint& s, int first_free) {
  if (s.xi == 0.0) return s.element >= first_free;
  return s.element + 1 >= first_free;
}

/// True when the sample point of device d takes part in contacts: it moves
/// with a free node and does not lie inside the element cut by a detachment.
bool takesPart(const ContactProblem& pb, size_t d, const SamplePoint& s) {
  if (s.element == (*pb.start)[d].cut_element && s.xi > 0.0) return false;
  return isFree(s, (*pb.workspaces)[d].first_free_node);
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

/// Orthonormal tangents of a contact plane: t1 along the device axis (its
/// part across n), t2 = n x t1.
std::array<Vec3, 2> tangentBasis(const Vec3& n, const Vec3& axis) {
  Vec3 t1 = axis - axis.dot(n) * n;
  if (t1.norm() < 1e-6) t1 = n.unitOrthogonal();
  t1.normalize();
  return {t1, n.cross(t1)};
}

/// Outer device of device d (-1: none).
int outerOf(const ContactProblem& pb, size_t d) {
  return pb.outer_of && d < pb.outer_of->size() ? (*pb.outer_of)[d] : -1;
}

/// Sample points of all devices at x. A point of an inner device within its
/// outer device's lumen, or less than a few radii beyond its tip, is marked:
/// it touches the outer device through the lumen constraint, never as a pair.
std::vector<PointRef> freePoints(const ContactProblem& pb, const std::vector<DeviceState>& x) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  std::vector<PointRef> pts;
  for (size_t d = 0; d < devices.size(); ++d) {
    const int outer = outerOf(pb, d);
    const double reach = outer < 0
                             ? 0.0
                             : x[outer].inserted_length + 4.0 * devices[outer].node_radius.back() +
                                   devices[outer].elements.back().length;
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& sp = samples[d][k];
      if (sp.element == x[d].cut_element && sp.xi > 0.0) continue;  // the detachment's gap
      const double s = materialCoordinate(devices[d], sp);
      const bool held =
          outer >= 0 && !detached(x[d], sp) && pathLength(devices[d], x[d], s) < reach;
      pts.push_back({takesPart(pb, d, sp), static_cast<int>(d), static_cast<int>(k), sp.element, s,
                     samplePosition(devices[d], x[d], sp), sp.radius, held ? outer : -1});
    }
  }
  return pts;
}

/// A wall contact of the previous step that starts this one: it carried a
/// force, or ended touching its plane (gap within `touching` [m]: a point
/// resting on the wall with no force, which the next step's free motion
/// pushes through again), and its point still takes part.
bool keptWallContact(const ContactProblem& pb, const Contact& prev, double touching) {
  if (prev.other_device >= 0 || prev.device >= static_cast<int>(pb.devices->size())) return false;
  if (!(prev.force > 0.0) && !(std::abs(prev.gap) <= touching)) return false;
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
                      std::vector<Contact>* contacts, std::vector<std::vector<int>>* contact_of) {
  if (!pb.previous || !pb.surface) return;
  for (const Contact& prev : *pb.previous) {
    if (!keptWallContact(pb, prev, touching)) continue;
    const int d = prev.device, k = prev.sample;
    if ((*contact_of)[d][k] >= 0) continue;
    const SamplePoint& s = (*pb.samples)[d][k];
    const SurfacePoint plane =
        projectToSurface(*pb.surface, samplePosition((*pb.devices)[d], (*pb.start)[d], s), s.radius,
                         pb.motion, 0.01, root);
    if (!plane.hit) continue;
    (*contact_of)[d][k] = static_cast<int>(contacts->size());
    Contact ct{d, k, plane.point, plane.normal, 0, 0};
    ct.force = prev.force;  // the friction solver's warm start
    ct.friction = prev.friction;
    contacts->push_back(ct);
  }
}

/// The paper's detection on [x_t, x_f]: per element of each device, the
/// sample point deepest beyond the wall at x_f becomes a contact, its plane
/// at the first root of its path (the activation loop adds any other point
/// of the element that stays beyond). A path that ends inside but left the
/// lumen on the way (a corner cut through tissue) is a crossing too, at its
/// first root. Only the chosen point's root is searched: the depth at x_f
/// ranks the others for one evaluation each. Returns true when a point
/// beyond the wall has no plane (beyond every vessel's support: the step
/// cannot be solved).
bool detectWallCrossings(const ContactProblem& pb, const std::vector<DeviceState>& xf,
                         const RootOptions& root, SampleFields* field,
                         std::vector<Contact>* contacts,
                         std::vector<std::vector<int>>* contact_of) {
  const auto& devices = *pb.devices;
  const auto& start = *pb.start;
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
      hit = projectToSurface(surface, p1, s.radius, pb.motion, 0.01, root);
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
    auto flush = [&]() {
      if (best.sample < 0) return;
      const SamplePoint& s = samples[d][best.sample];
      if (!best.hit.hit)
        best.hit = crossing(d, best.sample, samplePosition(devices[d], start[d], s),
                            samplePosition(devices[d], xf[d], s), nullptr);
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
      if (!takesPart(pb, d, s)) continue;
      const Vec3 p0 = samplePosition(devices[d], start[d], s);
      const Vec3 p1 = samplePosition(devices[d], xf[d], s);
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

/// Effect 'coaxial': a point of an inner device beyond its outer device's
/// lumen at x.
struct LumenViolation {
  int device, sample;
  LumenLocation location;
};

/// Points of inner devices beyond the lumen by more than `tolerance` at x:
/// all of them, or per inner element the deepest only.
std::vector<LumenViolation> lumenViolations(const ContactProblem& pb,
                                            const std::vector<DeviceState>& x, double tolerance,
                                            bool deepest_per_element) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  std::vector<LumenViolation> out;
  for (size_t d = 0; d < devices.size(); ++d) {
    const int outer = outerOf(pb, d);
    if (outer < 0) continue;
    int element = -1;
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& s = samples[d][k];
      if (!takesPart(pb, d, s) || detached(x[d], s)) continue;
      const LumenLocation loc = locateInLumen(devices[d], x[d], s, devices[outer], x[outer]);
      if (!loc.inside || loc.excess() <= tolerance) continue;
      const LumenViolation v{static_cast<int>(d), static_cast<int>(k), loc};
      if (deepest_per_element && s.element == element) {
        if (loc.excess() > out.back().location.excess()) out.back() = v;
        continue;
      }
      element = s.element;
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

std::string validateContactOptions(const ContactOptions& o) {
  std::ostringstream why;
  if (!(o.lcp.tolerance > 0.0 && o.lcp.tolerance <= 1e-3))
    why << "lcp tolerance must lie in (0, 1e-3] m";
  else if (o.lcp.max_iterations < 0 || o.lcp.max_iterations > 1000000)
    why << "lcp max_iterations must lie in [0, 1e6] (0: automatic)";
  else if (!(o.lcp.regularization >= 0.0 && o.lcp.regularization <= 1e-3))
    why << "lcp regularization must lie in [0, 1e-3]";
  else if (o.max_activation_loops < 1 || o.max_activation_loops > 1000)
    why << "max_activation_loops must lie in [1, 1000]";
  else if (o.curvature_loops < 1 || o.curvature_loops > 1000)
    why << "curvature_loops must lie in [1, 1000]";
  else if (o.max_subdivisions < 0 || o.max_subdivisions > 12)
    why << "max_subdivisions must lie in [0, 12]";
  else if (!(o.contact_spacing >= 1e-5 && o.contact_spacing <= 0.05))
    why << "contact_spacing must lie in [1e-5, 0.05] m";
  else if (!(o.penetration_tolerance >= 1e-9 && o.penetration_tolerance <= 1e-3))
    why << "penetration_tolerance must lie in [1e-9, 1e-3] m";
  else if (!(o.root.tolerance > 0.0 && o.root.tolerance <= 1e-6))
    why << "root tolerance must lie in (0, 1e-6] m";
  else if (!(o.friction_solver.tolerance > 0.0 && o.friction_solver.tolerance <= 1e-2))
    why << "friction tolerance must lie in (0, 1e-2]";
  else if (o.friction_solver.max_sweeps < 1 || o.friction_solver.max_sweeps > 1000000)
    why << "friction max_sweeps must lie in [1, 1e6]";
  return why.str();
}

namespace {

/// True when two rows of H are the same (parts, offsets, coefficients).
bool sameRow(const ContactRow& a, const ContactRow& b) {
  if (a.parts != b.parts) return false;
  for (int k = 0; k < a.parts; ++k)
    if (a.offset[k] != b.offset[k] || a.h[k] != b.h[k]) return false;
  return true;
}

/// Lends each device workspace's W storage to the step's DelassusBuffer
/// and takes it back on every way out: W keeps its capacity from step to
/// step (allocated afresh, the megabytes of a packed coil's W were page
/// faults again each step).
class WorkspaceStorageLease {
 public:
  WorkspaceStorageLease(std::vector<DeviceWorkspace>* ws, std::vector<DelassusBuffer>* W)
      : ws_(ws), W_(W) {
    swapAll();
  }
  ~WorkspaceStorageLease() { swapAll(); }
  WorkspaceStorageLease(const WorkspaceStorageLease&) = delete;
  WorkspaceStorageLease& operator=(const WorkspaceStorageLease&) = delete;

 private:
  void swapAll() {
    for (size_t d = 0; d < W_->size(); ++d) (*W_)[d].storage.swap((*ws_)[d].delassus_storage);
  }
  std::vector<DeviceWorkspace>* ws_;
  std::vector<DelassusBuffer>* W_;
};

/// What a device's workspace band (ws.inverse) holds: nothing valid, the
/// band of A^-1, of (A + C)^-1.
enum class Band { kNone, kOfA, kOfCurved };

/// C (contact/wall_curvature.h) of the wall contacts with a force, per
/// device; A + C into the workspace's `curved_system`. (*curved)[d] says
/// whether device d has such a term (else A alone). A + C is factorised
/// where W will need it: for a device with at least kChainDelassusMinRows
/// contacts, as its band (ws.inverse, whose block LDL^T also serves the
/// solves), else by CHOLMOD (`curved`). (*band)[d] is updated; a band of
/// A + C left from before becomes kNone.
void factorWallCurvature(const ContactProblem& pb, const std::vector<Contact>& contacts,
                         const std::vector<DeviceState>& x, std::vector<ChainMatrix>* C,
                         std::vector<char>* curved, std::vector<Band>* band) {
  const auto& devices = *pb.devices;
  auto& ws = *pb.workspaces;
  const auto& samples = *pb.samples;
  const size_t nd = devices.size();
  C->assign(nd, ChainMatrix());
  curved->assign(nd, 0);
  for (Band& b : *band)
    if (b == Band::kOfCurved) b = Band::kNone;
  std::vector<int> rows(nd, 0);  // contacts with a part on each device (its rows of H)
  for (const Contact& ct : contacts) {
    ++rows[ct.device];
    if (ct.other_device >= 0 && ct.other_device != ct.device) ++rows[ct.other_device];
  }
  for (const Contact& ct : contacts) {
    if (ct.other_device >= 0 || !(ct.force > 0.0)) continue;
    const int d = ct.device;
    const SamplePoint& s = samples[d][ct.sample];
    const int e = s.element;
    if (e + 1 < ws[d].first_free_node) continue;  // both nodes held
    std::array<Vec3, 2> t;
    const Eigen::Matrix2d S =
        wallCurvature(*pb.surface, ct.point, ct.normal, s.radius, pb.motion, &t);
    if (S.isZero(0.0)) continue;
    Eigen::Matrix<double, 2, 12> R;
    R.row(0) = contactRow(devices[d], x[d], s, t[0]);
    R.row(1) = contactRow(devices[d], x[d], s, t[1]);
    const Eigen::Matrix<double, 12, 12> Ce = ct.force * R.transpose() * S * R;
    ChainMatrix& Cd = (*C)[d];
    if (Cd.numBlocks() == 0) {
      Cd.resize(devices[d].num_nodes);
      Cd.setZero();
    }
    Cd.diag[e] += Ce.topLeftCorner<6, 6>();
    Cd.diag[e + 1] += Ce.bottomRightCorner<6, 6>();
    Cd.upper[e] += Ce.topRightCorner<6, 6>();
  }
  for (size_t d = 0; d < nd; ++d) {
    DeviceWorkspace& w = ws[d];
    const int n = w.factor.size();
    if ((*C)[d].numBlocks() == 0 || n == 0) continue;
    ChainMatrix& Ac = w.curved_system;  // storage kept across loops and steps
    Ac = w.system;
    for (int i = 0; i < Ac.numBlocks(); ++i) {
      Ac.diag[i] += (*C)[d].diag[i];
      if (i + 1 < Ac.numBlocks()) Ac.upper[i] += (*C)[d].upper[i];
    }
    // (C is positive semi-definite, so this should not fail; if it does, A.)
    if (rows[d] >= kChainDelassusMinRows) {
      const bool ok = w.inverse.compute(Ac, w.first_free_node);
      (*band)[d] = ok ? Band::kOfCurved : Band::kNone;
      if (ok) {
        (*curved)[d] = 1;
        continue;
      }
    }
    (*curved)[d] = w.curved.factorize(Ac, w.first_free_node) ? 1 : 0;
  }
}

/// The QP step's free motion about the iterate dq for the devices with a
/// curvature term: (*dq_step)[d] = (A + C)^-1 (A dq_free + C dq_k), and
/// their factor that of A + C. Others keep A and dq_free. The solve uses
/// the band's block LDL^T where it holds A + C, else the device's factor
/// of A + C.
void curvedFreeMotion(const ContactProblem& pb, const std::vector<ChainMatrix>& C,
                      const std::vector<char>& curved, const std::vector<Band>& band,
                      const std::vector<VecX>& dq, std::vector<VecX>* dq_step,
                      std::vector<const ChainFactor*>* factor) {
  auto& ws = *pb.workspaces;
  for (size_t d = 0; d < curved.size(); ++d) {
    if (!curved[d]) continue;
    DeviceWorkspace& w = ws[d];
    const int n = w.factor.size(), held = 6 * w.first_free_node;
    VecX free = (*dq_step)[d], iterate = dq[d];
    free.head(held).setZero();
    iterate.head(held).setZero();
    VecX rhs = (w.system.multiply(free) + C[d].multiply(iterate)).tail(n);
    (*factor)[d] = band[d] == Band::kOfCurved ? &w.inverse.factor() : &w.curved;
    (*factor)[d]->solveInPlace(&rhs);
    (*dq_step)[d].tail(n) = rhs;
  }
}

}  // namespace

bool resolveContacts(const ContactProblem& pb, const ContactOptions& o,
                     std::vector<Contact>* contacts, ContactStats* st) {
  const auto& devices = *pb.devices;
  const auto& start = *pb.start;
  auto& ws = *pb.workspaces;
  const auto& samples = *pb.samples;
  const size_t nd = devices.size();
  contacts->clear();
  *st = ContactStats{};
  const RootOptions& root = o.root;

  // --- Detection on [x_t, x_f] -------------------------------------------
  auto t0 = Clock::now();
  std::vector<VecX> dq_free(nd), dq(nd);
  for (size_t d = 0; d < nd; ++d) dq_free[d] = dq[d] = ws[d].dq;
  const std::vector<DeviceState> xf = moved(start, dq_free);
  std::vector<std::vector<int>> contact_of(nd);  // sample -> contact index or -1
  for (size_t d = 0; d < nd; ++d) contact_of[d].assign(samples[d].size(), -1);
  // The field at each sample's x_t and at the loop's x, where a certified
  // ball does not spare it: the converged answer's paths are checked for
  // tunnels.
  std::vector<size_t> counts(nd);
  for (size_t d = 0; d < nd; ++d) counts[d] = samples[d].size();
  // The certified balls are kept across steps while the surface is at rest;
  // a moving surface stands still within a step (one snapshot, at the
  // step's end), so its balls serve this step's loops only.
  std::vector<std::vector<InteriorBall>> step_balls;
  std::vector<std::vector<InteriorBall>>* balls = nullptr;
  if (o.interior_balls) balls = pb.interior && pb.motion.empty() ? pb.interior : &step_balls;
  SampleFields field(pb.surface, counts, balls);
  // With wall contacts kept from the last step, the paper's detection runs
  // on the path to the first loop's iterate instead of the free motion's:
  // a device held by its contacts swings millimetres away from them in the
  // free motion, and crossings along that path are undone by the kept
  // contacts in the first loop anyway (options.detect_on_first_iterate).
  bool detect_later =
      o.detect_on_first_iterate && pb.surface && hasKeptWallContacts(pb, o.penetration_tolerance);
  // A point beyond the wall where no plane can be found.
  bool stranded = pb.surface && !detect_later &&
                  detectWallCrossings(pb, xf, root, &field, contacts, &contact_of);
  keepWallContacts(pb, root, o.penetration_tolerance, contacts, &contact_of);
  if (detect_later && contacts->empty()) {  // no kept contact found its plane
    detect_later = false;
    stranded = detectWallCrossings(pb, xf, root, &field, contacts, &contact_of);
  }
  // Device points closer than the sum of their radii at x_f.
  std::map<std::array<int, 4>, int> pair_contact;  // (device, sample, device, sample) -> contact
  auto normalOf = [&](const std::vector<DeviceState>& x, const PointRef& a, const PointRef& b) {
    return pairNormal(a.p, sampleTangent(x[a.device], samples[a.device][a.sample]), b.p,
                      sampleTangent(x[b.device], samples[b.device][b.sample]));
  };
  auto addPair = [&](const PointRef& a, const PointRef& b, const Vec3& n) {
    pair_contact[{a.device, a.sample, b.device, b.sample}] = static_cast<int>(contacts->size());
    Contact ct{a.device, a.sample, b.p, n, 0, 0, b.device, b.sample};
    ct.other = samples[b.device][b.sample];
    ct.separation = a.r + b.r;
    contacts->push_back(ct);
  };
  if (o.device_contact) {
    const auto tp = Clock::now();
    const std::vector<PointRef> pts = freePoints(pb, xf);
    for (const Pair& pr : findPairs(devices, pts, 0.0))
      addPair(pts[pr.a], pts[pr.b], normalOf(xf, pts[pr.a], pts[pr.b]));
    ++st->pair_passes;
    st->pairs_ms += msSince(tp);
  }
  // Inner devices' points beyond their outer device's lumen at x_f, and the
  // lumen contacts of the previous step that carried a force.
  const bool coaxial = pb.outer_of && !pb.outer_of->empty();
  std::map<std::array<int, 2>, int> lumen_contact;  // (device, sample) -> contact
  auto addLumen = [&](const LumenViolation& v) {
    lumen_contact[{v.device, v.sample}] = static_cast<int>(contacts->size());
    contacts->push_back(lumenContact(v, outerOf(pb, v.device)));
  };
  if (coaxial) {
    const auto tl = Clock::now();
    for (const LumenViolation& v : lumenViolations(pb, xf, 0.0, true)) addLumen(v);
    if (pb.previous)
      for (const Contact& prev : *pb.previous) {
        if (!prev.lumen || prev.force <= 0.0 || prev.device >= static_cast<int>(nd) ||
            outerOf(pb, prev.device) != prev.other_device)
          continue;
        const int d = prev.device, k = prev.sample, outer = prev.other_device;
        const SamplePoint& s = samples[d][k];
        if (lumen_contact.count({d, k}) || !takesPart(pb, d, s) || detached(start[d], s)) continue;
        const LumenViolation v{d, k,
                               locateInLumen(devices[d], xf[d], s, devices[outer], xf[outer])};
        if (!v.location.inside || v.location.across.norm() == 0.0) continue;
        addLumen(v);
        contacts->back().force = prev.force;  // the friction solver's warm start
        contacts->back().friction = prev.friction;
      }
    ++st->lumen_passes;
    st->lumen_ms += msSince(tl);
  }
  st->detection_ms += msSince(t0);

  bool solved = contacts->empty() && !stranded;
  const int dim = o.friction ? 3 : 1;
  std::vector<std::array<Vec3, 2>> tangents;  // per contact with friction: t1, t2
  std::vector<DeviceState> x = xf;
  std::vector<char> updated(contacts->size(), 0);  // plane already updated in this step
  std::vector<Band> band(nd, Band::kNone);         // what ws[d].inverse holds
  std::vector<ChainMatrix> curvature;              // C per device, kept once no longer updated
  // Per device the rows and W of the last loop that used the band (reused
  // while the band stays).
  std::vector<std::vector<ContactRow>> last_rows(nd);
  std::vector<DelassusBuffer> last_W(nd);
  const WorkspaceStorageLease lease(&ws, &last_W);
  std::vector<char> curved(nd, 0);  // device d steps with A + C
  for (int loop = 1; loop <= o.max_activation_loops && !solved; ++loop) {
    st->activation_loops = loop;
    const int c = static_cast<int>(contacts->size());
    const int m = dim * c;  // rows: per contact n (and t1, t2 with friction)
    if (o.friction) tangents.resize(c);

    // --- The wall's curvature: A + C and the QP step's free motion ----------
    t0 = Clock::now();
    std::vector<const ChainFactor*> factor(nd);
    std::vector<VecX> dq_step = dq_free;
    for (size_t d = 0; d < nd; ++d) factor[d] = &ws[d].factor;
    if (o.wall_curvature && pb.surface) {
      // C from the last loop's forces for the first curvature_loops loops;
      // later loops keep it (and the band of (A + C)^-1): at the answer
      // dq = dq_k, so C shapes the path, not the step's solution.
      if (loop <= o.curvature_loops) {
        const std::vector<Band> before = band;
        factorWallCurvature(pb, *contacts, x, &curvature, &curved, &band);
        for (size_t d = 0; d < nd; ++d) {
          if (band[d] != before[d] || band[d] == Band::kOfCurved) {
            last_rows[d].clear();  // W of another matrix: nothing to reuse
            last_W[d].size = 0;
          }
        }
      }
      curvedFreeMotion(pb, curvature, curved, band, dq, &dq_step, &factor);
    }
    st->curvature_ms += msSince(t0);

    // --- Delassus operator W = H A^-1 H^T, q = H x_f - delta ---------------
    t0 = Clock::now();
    MatX W_sum;                                // m x m, once a device's part is added
    const DelassusBuffer* W_device = nullptr;  // or one device's operator (its rows are all rows)
    VecX q(m), mu(o.friction ? c : 0);
    // Parts of each row per device: (row, sample, signed row of H).
    struct Part {
      int row, element;
      Row12 h;
    };
    std::vector<std::vector<Part>> parts(nd);
    // The rows are linearised at x, the configuration of the last loop (x_f
    // in the first): g(x_f + A^-1 H^T lambda) ~ g(x) + H (x_f - x) + W lambda.
    // Linearised at x_f throughout, a loop whose correction moves points far
    // from x_f (a pre-shaped tip squeezed into a narrow lumen springs open by
    // millimetres in the free motion) keeps stale rows and stops converging.
    // Adds the part's row of H at x; returns its share of H (x_f - x).
    auto addPart = [&](int row, int device, const SamplePoint& s, const Vec3& n, double sign) {
      const Row12 h = sign * contactRow(devices[device], x[device], s, n);
      parts[device].push_back({row, s.element, h});
      const int at = 6 * s.element;
      return h.dot(dq_step[device].segment<12>(at) - dq[device].segment<12>(at));
    };
    for (int i = 0; i < c; ++i) {
      Contact& ct = (*contacts)[i];
      const SamplePoint& s = samples[ct.device][ct.sample];
      const Vec3 p = samplePosition(devices[ct.device], x[ct.device], s);
      const int row = dim * i;
      q(row) = addPart(row, ct.device, s, ct.normal, 1.0);
      const SamplePoint* so = nullptr;
      Vec3 po = Vec3::Zero();
      if (ct.other_device < 0) {
        q(row) += ct.normal.dot(p - ct.point);
      } else {
        so = &ct.other;
        po = samplePosition(devices[ct.other_device], x[ct.other_device], *so);
        q(row) += ct.normal.dot(p - po) - ct.separation +
                  addPart(row, ct.other_device, *so, ct.normal, -1.0);
      }
      if (!o.friction) continue;
      // Tangent rows: q is the slip over the step (relative to the other
      // point for pairs).
      tangents[i] = tangentBasis(ct.normal, sampleTangent(x[ct.device], s));
      Vec3 slip = p - samplePosition(devices[ct.device], start[ct.device], s);
      if (so) slip -= po - samplePosition(devices[ct.other_device], start[ct.other_device], *so);
      mu(i) = so ? std::sqrt(s.friction * so->friction) : s.friction;
      for (int k = 0; k < 2; ++k) {
        const Vec3& t = tangents[i][k];
        q(row + 1 + k) = t.dot(slip) + addPart(row + 1 + k, ct.device, s, t, 1.0);
        if (so) q(row + 1 + k) += addPart(row + 1 + k, ct.other_device, *so, t, -1.0);
      }
    }
    std::vector<std::vector<int>> of_device(nd);  // rows with a part on each device
    std::vector<std::vector<ContactRow>> rows_of(nd);
    std::vector<MatX> Y(nd);  // A^-1 H^T where W came from the block solve
    std::vector<int> column_of_row;
    for (size_t d = 0; d < nd; ++d) {
      if (parts[d].empty()) continue;
      std::vector<ContactRow>& device_rows = rows_of[d];
      column_of_row.assign(m, -1);  // row -> its column in this device's operator
      for (const Part& pt : parts[d]) {
        const Row12& h = pt.h;
        const int offset = 6 * (pt.element - ws[d].first_free_node);
        int& column = column_of_row[pt.row];
        if (column < 0) {
          column = static_cast<int>(device_rows.size());
          of_device[d].push_back(pt.row);
          ContactRow row;
          row.offset[0] = offset;
          row.h[0] = h;
          device_rows.push_back(row);
        } else {  // a self contact: its second part on the same device
          ContactRow& row = device_rows[column];
          row.offset[1] = offset;
          row.h[1] = h;
          row.parts = 2;
        }
      }
      MatX Wd;
      const DelassusBuffer* kept = nullptr;  // the device's operator, kept for the next loop
      if (static_cast<int>(device_rows.size()) < kChainDelassusMinRows) {
        delassusOperator(*factor[d], device_rows, &Y[d], &Wd);
      } else {
        // The band of (A + C)^-1 whenever C changed, of A once a step, from
        // the factor this loop steps with.
        const Band wanted = curved[d] ? Band::kOfCurved : Band::kOfA;
        if (band[d] != wanted) {
          ws[d].inverse.computeFrom(*factor[d]);
          band[d] = wanted;
          last_rows[d].clear();  // nothing to reuse
          last_W[d].size = 0;
        }
        Y[d].resize(0, 0);
        // Rows unchanged since the last loop (same normal, and for a sample
        // at a node no tangent term) keep their entries among themselves.
        const std::vector<ContactRow>& before = last_rows[d];
        std::vector<char> changed(before.size(), 1);
        for (size_t r = 0; r < before.size() && r < device_rows.size(); ++r)
          changed[r] = !sameRow(before[r], device_rows[r]);
        updateChainDelassusOperator(ws[d].inverse, device_rows, changed, &last_W[d]);
        last_rows[d] = device_rows;
        kept = &last_W[d];
      }
      const MatXView Wdev = kept ? kept->view() : MatXView(Wd);  // this device's operator
      const auto& idx = of_device[d];
      bool identity = !W_device && W_sum.size() == 0 && static_cast<int>(idx.size()) == m;
      for (size_t a = 0; a < idx.size() && identity; ++a) identity = idx[a] == static_cast<int>(a);
      if (identity) {  // one device holds every row, in order: W is its operator
        if (kept)
          W_device = kept;  // last_W[d], unchanged until the next loop
        else
          W_sum.swap(Wd);
        continue;
      }
      if (W_device) {  // a device before held every row, and this one shares some
        W_sum = W_device->view();
        W_device = nullptr;
      }
      if (W_sum.size() == 0) W_sum = MatX::Zero(m, m);
      for (size_t b = 0; b < idx.size(); ++b)  // column by column (W is column-major)
        for (size_t a = 0; a < idx.size(); ++a) W_sum(idx[a], idx[b]) += Wdev(a, b);
    }
    if (!W_device && W_sum.size() == 0) W_sum = MatX::Zero(m, m);
    const MatXView W = W_device ? W_device->view() : MatXView(W_sum);
    st->delassus_ms += msSince(t0);

    // --- Status method (or the chosen solver; NSGS with friction) -----------
    t0 = Clock::now();
    VecX lambda;
    LcpStatus status;
    if (o.friction) {
      lambda.resize(m);  // warm start: the last loop's (or step's) forces
      for (int i = 0; i < c; ++i) {
        const Contact& ct = (*contacts)[i];
        lambda.segment<3>(3 * i) << std::max(0.0, ct.force), tangents[i][0].dot(ct.friction),
            tangents[i][1].dot(ct.friction);
      }
      FrictionStats fs;
      status = solveFrictionalContact(W, q, mu, o.friction_solver, &lambda, &fs);
      st->lcp_iterations += fs.sweeps;
      st->lcp_residual = fs.residual;
      st->sliding_contacts = fs.sliding;
      ++st->friction_solves;
    } else {
      // Warm start: the forces of the last loop (or, for contacts that
      // persist, of the last step); the new contacts start inactive.
      lambda.resize(c);
      for (int i = 0; i < c; ++i) lambda(i) = std::max(0.0, (*contacts)[i].force);
      LcpOptions lo = o.lcp;
      lo.warm_start = true;
      LcpStats ls;
      status = solveLcp(W, q, lo, &lambda, &ls);
      st->lcp_iterations += ls.iterations;
      st->lcp_residual = ls.residual;
    }
    st->lcp_ms += msSince(t0);
    st->contacts = c;
    if (pb.record) *pb.record = {MatX(W), q, lambda, mu};
    if (status != LcpStatus::kSolved) {  // the caller subdivides
      st->lcp_status = status;
      return false;
    }

    // --- Correction x = x_f + A^-1 H^T lambda --------------------------------
    t0 = Clock::now();
    for (size_t d = 0; d < nd; ++d) {
      dq[d] = dq_step[d];
      const auto& idx = of_device[d];
      if (idx.empty()) continue;
      VecX l(idx.size());
      for (size_t j = 0; j < idx.size(); ++j) l(j) = lambda(idx[j]);
      const int n = factor[d]->size();
      if (Y[d].size() > 0) {
        dq[d].tail(n) += Y[d] * l;
      } else {
        VecX correction = contactForce(n, rows_of[d], l);
        ws[d].inverse.solveInPlace(&correction);  // the LDL^T of the band's matrix
        dq[d].tail(n) += correction;
      }
    }
    x = moved(start, dq);
    for (int i = 0; i < c; ++i) {
      Contact& ct = (*contacts)[i];
      ct.force = lambda(dim * i);
      if (o.friction)
        ct.friction = lambda(3 * i + 1) * tangents[i][0] + lambda(3 * i + 2) * tangents[i][1];
    }
    st->correction_ms += msSince(t0);

    // --- Re-detection on x: plane updates and new contacts ------------------
    t0 = Clock::now();
    solved = true;
    // The first loop after kept contacts: the paper's detection on x_t -> x.
    const int fresh_from = static_cast<int>(contacts->size());
    if (loop == 1 && detect_later) {
      detectWallCrossings(pb, x, root, &field, contacts, &contact_of);  // (stranded: seen below)
      updated.resize(contacts->size(), 0);
      solved = static_cast<int>(contacts->size()) == fresh_from;
    }
    double deepest = 0.0;  // over all points at x: the step's penetration if this is the last loop
    for (size_t d = 0; d < nd && pb.surface; ++d) {
      for (size_t k = 0; k < samples[d].size(); ++k) {
        const SamplePoint& s = samples[d][k];
        if (!takesPart(pb, d, s)) continue;
        const Vec3 p = samplePosition(devices[d], x[d], s);
        double depth_bound = 0.0;
        if (field.endWithinTolerance(d, k, p, s.radius, pb.motion, o.penetration_tolerance,
                                     &depth_bound)) {
          deepest = std::max(deepest, depth_bound);
          continue;
        }
        const FieldSample& g = field.end(d, k, p, s.radius, pb.motion);
        deepest = std::max(deepest, depthOf(g));
        if (depthOf(g) <= o.penetration_tolerance) continue;
        solved = false;
        if (contact_of[d][k] >= fresh_from) continue;  // just detected: solved first
        const Vec3 p0 = samplePosition(devices[d], start[d], s);
        SurfacePoint plane = projectToSurface(*pb.surface, p, s.radius, pb.motion, 0.01, root);
        if (!plane.hit) {
          // No projection (beyond every vessel's support the field is flat):
          // the wall where the point's path from x_t crossed it.
          const SurfacePoint hit = firstRoot(*pb.surface, p0, p, s.radius, pb.motion, root);
          if (hit.hit && !hit.started_outside) plane = hit;
          // At x_t already within the tolerance band beyond the wall: where
          // the path, having crossed the lumen, leaves it through the far
          // wall; if it never enters the lumen, the wall nearest to where it
          // left the support (the point slid along its plane, millimetres
          // round a bend). The plane where it was would hold nothing: the
          // point satisfies it, and it was added again in every loop.
          if (hit.started_outside) {
            plane = farExit(*pb.surface, p0, p, s.radius, pb.motion, root);
            if (!plane.hit) plane = lastWallAlong(*pb.surface, p0, p, s.radius, pb.motion, root);
          }
        }
        const int existing = contact_of[d][k];
        if (existing >= 0 && !updated[existing]) {
          // The paper's update: the tangent plane where x projects.
          if (!plane.hit) continue;
          Contact& ct = (*contacts)[existing];
          ct.point = plane.point;
          ct.normal = plane.normal;
          updated[existing] = 1;
          continue;
        }
        if (existing < 0) {
          SurfacePoint hit = firstRoot(*pb.surface, p0, p, s.radius, pb.motion, root);
          if (hit.hit && !hit.started_outside) plane = hit;
        }
        // A new contact, or a second plane for a point violated again after
        // its update (a concave wall: updates alone can oscillate; the extra
        // plane only shrinks the admissible set, so the loop converges).
        if (!plane.hit) continue;
        contact_of[d][k] = static_cast<int>(contacts->size());
        contacts->push_back(
            {static_cast<int>(d), static_cast<int>(k), plane.point, plane.normal, 0, 0});
        updated.push_back(0);
      }
    }
    st->max_penetration_m = deepest;
    if (o.device_contact) {
      const auto tp = Clock::now();
      ++st->pair_passes;
      const std::vector<PointRef> pts = freePoints(pb, x);
      for (const Pair& pr : findPairs(devices, pts, -o.penetration_tolerance)) {
        solved = false;
        const PointRef &a = pts[pr.a], &b = pts[pr.b];
        const auto it = pair_contact.find({a.device, a.sample, b.device, b.sample});
        if (it != pair_contact.end() && !updated[it->second]) {
          Contact& ct = (*contacts)[it->second];  // the pair's normal at x
          ct.normal = normalOf(x, a, b);
          ct.point = b.p;
          updated[it->second] = 1;
        } else {
          addPair(a, b, normalOf(x, a, b));
          updated.push_back(0);
        }
      }
      st->pairs_ms += msSince(tp);
    }
    if (coaxial) {
      // Like wall contacts: a point still beyond the lumen has its contact
      // moved to the tangent plane where it now lies, once; beyond it again,
      // it gets a second plane (updates alone converge slowly: measured on
      // carotid_catheter, nearly every step needed halving).
      const auto tl = Clock::now();
      ++st->lumen_passes;
      for (const LumenViolation& v : lumenViolations(pb, x, o.penetration_tolerance, false)) {
        solved = false;
        deepest = std::max(deepest, v.location.excess());
        st->max_penetration_m = deepest;
        const auto it = lumen_contact.find({v.device, v.sample});
        if (it != lumen_contact.end() && !updated[it->second]) {
          const Contact fresh = lumenContact(v, outerOf(pb, v.device));
          Contact& ct = (*contacts)[it->second];
          ct.point = fresh.point;
          ct.normal = fresh.normal;
          ct.other = fresh.other;
          ct.separation = fresh.separation;
          updated[it->second] = 1;
        } else {
          addLumen(v);
          updated.push_back(0);
        }
      }
      st->lumen_ms += msSince(tl);
    }
    // Converged: but did a point's path from x_t pass through a wall into
    // another lumen? Only the answer is checked, not every iterate (the
    // first loops' iterates may swing millimetres through the neck of an
    // aneurysm; later loops bring them back). Such a point gets the wall
    // where it left as a new plane, and the loop goes on.
    const bool converged = solved;
    for (size_t d = 0; d < nd && converged && pb.surface; ++d) {
      for (size_t k = 0; k < samples[d].size(); ++k) {
        const SamplePoint& s = samples[d][k];
        if (!takesPart(pb, d, s)) continue;
        const Vec3 p0 = samplePosition(devices[d], start[d], s);
        const Vec3 p = samplePosition(devices[d], x[d], s);
        if (field.chordInside(d, k, p0, p)) continue;
        const SurfacePoint exit =
            tunnelExit(*pb.surface, p0, field.start(d, k, p0, s.radius, pb.motion), p,
                       field.end(d, k, p, s.radius, pb.motion), s.radius, pb.motion, root);
        if (!exit.hit) continue;
        ++st->tunnelled;
        solved = false;
        contact_of[d][k] = static_cast<int>(contacts->size());
        contacts->push_back(
            {static_cast<int>(d), static_cast<int>(k), exit.point, exit.normal, 0, 0});
        updated.push_back(0);
      }
    }
    st->detection_ms += msSince(t0);
  }

  // Final gaps, forces, deepest point.
  for (auto& ct : *contacts) {
    const SamplePoint& s = samples[ct.device][ct.sample];
    const Vec3 p = samplePosition(devices[ct.device], x[ct.device], s);
    if (ct.other_device < 0) {
      ct.gap = ct.normal.dot(p - ct.point);
    } else {
      const Vec3 po = samplePosition(devices[ct.other_device], x[ct.other_device], ct.other);
      ct.gap = ct.normal.dot(p - po) - ct.separation;
      if (!ct.lumen)  // (lumen excess: measured by the last loop's pass)
        st->max_penetration_m = std::max(st->max_penetration_m, -((p - po).norm() - ct.separation));
    }
    if (ct.force > 0.0) ++st->active_contacts;
    if (ct.force <= 0.0) ct.friction.setZero();
  }
  // The deepest wall penetration was measured by the last loop's pass over
  // the points at x (without contacts, no point crossed: 0).
  for (size_t d = 0; d < nd; ++d) {
    ws[d].dq = dq[d];
  }
  return solved;
}

}  // namespace evsim
