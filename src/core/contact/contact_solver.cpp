// Contact resolution of one step: the activation loop of the paper
// (section 2.2), one page. Each phase is a function of its own:
// contact_detection.cpp finds the contacts, contact_system.cpp forms and
// corrects the loop's linear problem, this file solves it (the status
// method, or the frictional solver) and runs the loop. activation_loop.h
// holds the state the phases share.
#include "endovascular_sim/contact/contact_solver.h"

#include <algorithm>
#include <sstream>

#include "activation_loop.h"
#include "contact_workspace_kept.h"

namespace evsim {

namespace activation {

LoopState::LoopState(const ContactProblem& pb, std::vector<Contact>* contact_list)
    : contacts(contact_list) {
  const size_t nd = pb.devices->size();
  dq_free.resize(nd);
  dq.resize(nd);
  for (size_t d = 0; d < nd; ++d) dq_free[d] = dq[d] = (*pb.workspaces)[d].dq;
  at_start.reset(pb, pb.start);
  contact_of.resize(nd);
  for (size_t d = 0; d < nd; ++d) contact_of[d].assign((*pb.samples)[d].size(), -1);
  lumen_of.resize(nd);  // (for inner devices only)
  for (size_t d = 0; d < nd; ++d)
    if (outerOf(pb, d) >= 0) lumen_of[d].assign((*pb.samples)[d].size(), -1);
  band.assign(nd, Band::kNone);
  curved.assign(nd, 0);
  last_rows.resize(nd);
  last_W.resize(nd);
}

void SamplePositions::reset(const ContactProblem& pb, const std::vector<DeviceState>* x) {
  pb_ = &pb;
  x_ = x;
  const size_t nd = pb.samples->size();
  first_.resize(nd);
  int count = 0;
  for (size_t d = 0; d < nd; ++d) {
    first_[d] = count;
    count += static_cast<int>((*pb.samples)[d].size());
  }
  p_.resize(count);
  known_.assign(count, 0);
}

void SamplePositions::place(int d, int k, int i) {
  // The whole element at once: passes ask for every point in turn, and its
  // tangents are formed once for all of its points.
  const std::vector<SamplePoint>& samples = (*pb_->samples)[d];
  const int element = samples[k].element, count = static_cast<int>(samples.size());
  int lo = k, hi = k + 1;
  while (lo > 0 && samples[lo - 1].element == element) --lo;
  while (hi < count && samples[hi].element == element) ++hi;
  samplePositions((*pb_->devices)[d], (*x_)[d], &samples[lo], hi - lo, &p_[i - (k - lo)]);
  std::fill(known_.begin() + (i - (k - lo)), known_.begin() + (i + (hi - k)), 1);
}

namespace {

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

/// The loop's forces: W lambda + q >= 0 _|_ lambda >= 0 by the chosen LCP
/// solver, or with friction the frictional problem; warm-started from the
/// last loop's (or, for contacts that persist, the last step's) forces.
LcpStatus solveForces(const ContactProblem& pb, const ContactOptions& o,
                      const std::vector<Contact>& contacts, const LoopSystem& sys, VecX* lambda,
                      ContactStats* st) {
  const int c = sys.c;
  if (pb.effects.friction) {
    const MatXView W = sys.W();
    lambda->resize(sys.m);
    for (int i = 0; i < c; ++i) {
      const Contact& ct = contacts[i];
      lambda->segment<3>(3 * i) << std::max(0.0, ct.force), sys.tangents[i][0].dot(ct.friction),
          sys.tangents[i][1].dot(ct.friction);
    }
    FrictionStats fs;
    const LcpStatus status =
        solveFrictionalContact(W, sys.q, sys.mu, o.friction_solver, lambda, &fs);
    st->lcp_iterations += fs.sweeps;
    st->lcp_residual = fs.residual;
    st->sliding_contacts = fs.sliding;
    ++st->friction_solves;
    return status;
  }
  // The new contacts start inactive.
  lambda->resize(c);
  for (int i = 0; i < c; ++i) (*lambda)(i) = std::max(0.0, contacts[i].force);
  LcpStats ls;
  LcpWorkspace* kept = pb.kept ? &pb.kept->kept().lcp : nullptr;
  const LcpStatus status = sys.columns ? solveLcp(*sys.columns, sys.q, o.lcp, lambda, &ls, kept)
                                       : solveLcp(sys.W(), sys.q, o.lcp, lambda, &ls, kept);
  st->lcp_iterations += ls.iterations;
  st->lcp_residual = ls.residual;
  return status;
}

/// Final gaps, active contacts, and the deepest device-pair overlap.
void finishContacts(const ContactProblem& pb, const std::vector<DeviceState>& x,
                    std::vector<Contact>* contacts, ContactStats* st) {
  const auto& devices = *pb.devices;
  const auto& samples = *pb.samples;
  for (auto& ct : *contacts) {
    const SamplePoint& s = contactPointOf(ct, samples);
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
}

/// After a loop's correction: re-detection on x (plane updates and new
/// contacts; the first loop after kept contacts runs the paper's detection
/// on x_t -> x first), then, once nothing is beyond a wall, the tunnel check
/// and the lumen springs' settling. True when the loop's answer stands.
bool loopSolved(const ContactProblem& pb, const ContactOptions& o, int loop, bool detect_later,
                const LoopSystem& sys, fields::SampleFields* field, LoopState* s,
                ContactStats* st) {
  std::vector<Contact>* contacts = s->contacts;
  const int fresh_from = static_cast<int>(contacts->size());
  bool solved = true;
  if (loop == 1 && detect_later) {
    detectWallCrossings(pb, o.root, field, s);  // (stranded: below)
    s->updated.resize(contacts->size(), 0);
    solved = static_cast<int>(contacts->size()) == fresh_from;
  }
  solved = redetect(pb, o, field, fresh_from, s, st) && solved;
  // Converged: but did a point's path from x_t pass through a wall into
  // another lumen? Only the answer is checked, not every iterate (the
  // first loops' iterates may swing millimetres through the neck of an
  // aneurysm; later loops bring them back). Such a point gets the wall
  // where it left as a new plane, and the loop goes on.
  if (solved) solved = checkTunnels(pb, o, field, s, st);
  // The lumen's curvature springs leave no spurious force (at the last
  // loop allowed, what they leave stands: no point is beyond a wall).
  if (solved && loop < o.max_activation_loops)
    solved = lumenSpringsSettled(sys, *s, o.lumen_settle);
  return solved;
}

}  // namespace
}  // namespace activation

bool resolveContacts(const ContactProblem& pb, const ContactOptions& o,
                     std::vector<Contact>* contacts, ContactStats* st, StageTimer* timer) {
  using namespace activation;
  StageTimer own;
  StageTimer& clock = timer ? *timer : own;
  auto& ws = *pb.workspaces;
  contacts->clear();
  *st = ContactStats{};
  ContactTimes& times = st->times;

  // --- Detection on [x_t, x_f] ----------------------------------------------
  clock.begin();
  LoopState s(pb, contacts);
  if (pb.end) s.x.swap(*pb.end);  // its storage, for the iterates (placeIterate)
  // The field at each sample's x_t and at the loop's x, where a certified
  // ball does not spare it. The balls are kept across steps; a moving
  // surface stands still within a step (one snapshot, at the step's end),
  // and a ball certified at an earlier snapshot follows it (followBall).
  std::vector<size_t> counts(s.contact_of.size());
  for (size_t d = 0; d < counts.size(); ++d) counts[d] = s.contact_of[d].size();
  std::vector<std::vector<InteriorBall>> step_balls;
  std::vector<std::vector<InteriorBall>>* balls = nullptr;
  if (o.interior_balls) balls = pb.interior ? pb.interior : &step_balls;
  fields::SampleFields field(pb.surface, counts, balls, &pb.motion);
  bool detect_later = false;
  // The first loop about the last step's forces applied to x_f: a coil
  // pressed into an aneurysm springs half a millimetre open in its free
  // motion, and the turns that touch again at the first iterate took a
  // second loop (options.predict_first_iterate).
  const bool predicted = o.predict_first_iterate && predictFirstIterate(pb, &s);
  if (!predicted) placeAtFreeMotion(pb, &s);
  bool stranded = detectOnFreeMotion(pb, o, &field, &s, &detect_later, st);
  if (predicted && (contacts->empty() || stranded)) {  // nothing holds it there: from x_f
    restartAtFreeMotion(pb, &s);
    stranded = detectOnFreeMotion(pb, o, &field, &s, &detect_later, st);
  }
  clock.end(&times.detection_ms);

  // --- The activation loop ----------------------------------------------------
  bool solved = contacts->empty() && !stranded;
  LcpStatus last_status = LcpStatus::kSolved;
  const int dim = pb.effects.friction ? 3 : 1;
  s.updated.assign(contacts->size(), 0);
  const WorkspaceStorageLease lease(&ws, &s.last_W);
  for (int loop = 1; loop <= o.max_activation_loops && !solved; ++loop) {
    st->activation_loops = loop;
    s.loop = loop;
    LoopSystem sys;
    sys.c = static_cast<int>(contacts->size());
    sys.m = dim * sys.c;
    clock.begin();
    prepareFreeMotion(pb, o, loop, &s, &sys);  // A, or A + C: the wall's curvature
    clock.end(&times.curvature_ms);

    clock.begin();
    formContactProblem(pb, o, &s, &sys);  // H, q at x; W = H A^-1 H^T
    clock.end(&times.delassus_ms);
    st->on_demand_loops += sys.columns ? 1 : 0;
    st->kept_rows += sys.kept_rows;

    VecX lambda;
    clock.begin();
    const LcpStatus status = solveForces(pb, o, *contacts, sys, &lambda, st);
    clock.end(&times.lcp_ms);
    st->contacts = sys.c;
    if (loop == 1) st->first_rows = sys.c;
    if (pb.record)
      *pb.record = {sys.columns ? sys.columns->dense() : MatX(sys.W()), sys.q, lambda, sys.mu};
    // An unsolved LCP's answer (the regularised problem's) is an iterate
    // the loop may go on from, never the step's answer (below).
    last_status = status;
    if (status != LcpStatus::kSolved && status != LcpStatus::kUnsolved) {  // the caller subdivides
      st->lcp_status = status;
      return false;
    }

    clock.begin();
    correctMotion(pb, sys, lambda, &s);  // x = x_f + A^-1 H^T lambda
    clock.end(&times.correction_ms);

    clock.begin();
    solved = loopSolved(pb, o, loop, detect_later, sys, &field, &s, st);
    clock.end(&times.detection_ms);
  }

  if (last_status == LcpStatus::kUnsolved) {  // the points placed or not, the forces no answer
    st->lcp_status = last_status;
    solved = false;
  }
  if (st->activation_loops > 0)
    for (size_t i = st->first_rows; i < contacts->size(); ++i) {
      const Contact& ct = (*contacts)[i];
      ++(ct.lumen               ? st->late_rows.lumen
         : ct.other_device >= 0 ? st->late_rows.pair
                                : st->late_rows.wall);
    }
  // The deepest wall penetration was measured by the last loop's pass over
  // the points at x (without contacts, no point crossed: 0).
  finishContacts(pb, s.x, contacts, st);
  for (size_t d = 0; d < ws.size(); ++d) ws[d].dq = s.dq[d];
  if (pb.end) pb.end->swap(s.x);  // x_t (+) s.dq: placeIterate's, as commitMotion's
  return solved;
}

ContactTimes& ContactTimes::operator+=(const ContactTimes& o) {
  detection_ms += o.detection_ms;
  curvature_ms += o.curvature_ms;
  delassus_ms += o.delassus_ms;
  lcp_ms += o.lcp_ms;
  correction_ms += o.correction_ms;
  device_contact_ms += o.device_contact_ms;
  coaxial_ms += o.coaxial_ms;
  return *this;
}

void ContactStats::addSubStep(const ContactStats& sub) {
  contacts = sub.contacts;
  active_contacts = sub.active_contacts;
  sliding_contacts = sub.sliding_contacts;
  friction_solves += sub.friction_solves;
  activation_loops = std::max(activation_loops, sub.activation_loops);
  lcp_iterations += sub.lcp_iterations;
  lcp_residual = std::max(lcp_residual, sub.lcp_residual);
  max_penetration_m = sub.max_penetration_m;
  deepest_device = sub.deepest_device;
  deepest_point = sub.deepest_point;
  lcp_status = sub.lcp_status;
  tunnels += sub.tunnels;
  pair_passes += sub.pair_passes;
  lumen_passes += sub.lumen_passes;
  on_demand_loops += sub.on_demand_loops;
  kept_rows += sub.kept_rows;
  slid_forces += sub.slid_forces;
  first_rows = sub.first_rows;
  late_rows += sub.late_rows;
}

}  // namespace evsim
