// The phases of one step's contact resolution (contact_solver.h), as
// resolveContacts calls them, and the state they share. Internal to the
// contact layer.
//
//   contact_detection.cpp  detection on [x_t, x_f] (the paper's first roots),
//                     kept contacts, device pairs, lumen contacts; the
//                     re-detection at each loop's x and the tunnel check
//   contact_system.cpp  the loop's linear problem: the wall-curvature term
//                     A + C, the rows of H and q at x, W = H A^-1 H^T, and
//                     the correction x = x_f + A^-1 H^T lambda
//   delassus_columns.cpp  W formed column by column as the status method
//                     reads it, where that is cheaper than whole
//   lumen_curvature.cpp  effect 'coaxial': the lumen's curvature as compliant
//                     rows on the relative slide, eliminated from W and q
//   contact_solver.cpp  the loop itself and the LCP (or frictional) solve
#pragma once

#include <Eigen/Cholesky>
#include <array>
#include <chrono>
#include <map>
#include <memory>
#include <vector>

#include "delassus_columns.h"
#include "device_pairs.h"
#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/contact/delassus.h"
#include "endovascular_sim/mechanics/chain_matrix.h"
#include "sample_fields.h"

namespace evsim::activation {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Contacts of one device from which its A + C (the wall's curvature) is
/// factorised as the band of (A + C)^-1 with its block LDL^T at once,
/// rather than as a chain factor alone: W will come from the band
/// (contact_system.cpp, fromBand: the block solve costs c (n - f)
/// column-blocks, the band 4 n and its sweep 24 c).
constexpr int kChainCurvedBandRows = 16;

/// What a device's workspace band (ws.inverse) holds: nothing valid, the
/// band of A^-1, of (A + C)^-1.
enum class Band { kNone, kOfA, kOfCurved };

/// A part of a row of H on one device: (row, element, signed row of H).
struct RowPart {
  int row, element;
  Row12 h;
};

/// A row of the lumen's curvature (lumen_curvature.cpp): across the outer
/// axis at a lumen contact, on the inner point (part 0) and the outer axis
/// point (part 1, negated), of stiffness k = lambda / rho.
struct LumenSpring {
  std::array<RowPart, 2> part;
  std::array<int, 2> device;
  std::array<int, 2> first_free_node;  // of each part's device
  double rho;                          // the clearance [m]
  double k;                            // [N/m]
};

/// The wall's curvature term C of one device (wall_curvature.h): a 12 x 12
/// block on the nodes (e, e + 1) per wall contact with a force on element
/// e, zero elsewhere (a few blocks on a chain of hundreds).
struct CurvatureTerm {
  std::vector<int> element;
  std::vector<Mat12> block;
  bool empty() const { return element.empty(); }
};

/// The sample points' positions at one configuration, each computed on
/// first use: the passes of detection (crossings, re-detection, tunnels)
/// ask for the same points at x_t and at the loop's x.
class SamplePositions {
 public:
  /// Forgets the positions: from now on those at *x (kept by address).
  void reset(const ContactProblem& pb, const std::vector<DeviceState>* x);
  /// Sample k of device d at *x [m]. Inline: every pass asks for every
  /// point, and most are known already.
  const Vec3& at(int d, int k) {
    const int i = first_[d] + k;
    if (!known_[i]) place(d, k, i);
    return p_[i];
  }

 private:
  void place(int d, int k, int i);  // computes sample k of device d into entry i

  const ContactProblem* pb_{nullptr};
  const std::vector<DeviceState>* x_{nullptr};
  std::vector<int> first_;  // per device, the entry of its first sample
  std::vector<Vec3> p_;     // every device's samples, one after the other
  std::vector<char> known_;
};

/// A contact's normal row of H as a loop formed it (one part per device
/// point: one for a wall, two for a pair), with what it was formed from:
/// its points, its normal, and the node tangents of each point's element.
/// formRows reuses it, bit for bit, while its points and normal are the
/// same and no node tangent turned by more than options.row_turn, on a
/// device whose last loop took W from the band: W's entries among
/// unchanged rows are then kept from the last loop (deviceOperator). A
/// kept row's rotational terms (h10 L t x n, |h10| <= 4/27) differ from
/// the row at x by at most row_turn of theirs, so the gap the loop's
/// linear problem predicts differs from the linearisation at x by at most
/// 4/27 row_turn L times the correction's turn: 1.5e-8 m for 2e-2 and
/// 1e-2 rad over a 0.5 mm element, 1.5 % of the wall's penetration
/// tolerance. The loop's detection at x checks the true gaps either way.
struct FormedRow {
  int parts{0};  // 0: none formed
  Vec3 normal{Vec3::Zero()};
  std::array<int, 2> element{};
  std::array<double, 2> xi{};
  std::array<Row12, 2> h{};
  std::array<std::array<Vec3, 2>, 2> tangent{};  // per part: its element's node tangents
};

/// What the activation loop of one step carries from loop to loop.
struct LoopState {
  /// dq = dq_free; x not yet placed (placeAtFreeMotion or predictFirstIterate).
  LoopState(const ContactProblem& pb, std::vector<Contact>* contacts);

  std::vector<VecX> dq_free;   // per device: the free motion x_f - x_t
  std::vector<VecX> dq;        // the loop's iterate x - x_t
  std::vector<DeviceState> x;  // x_t (+) dq: the configuration the rows are linearised at
  int loop{0};                 // the activation loop under way (1, 2, ...)
  bool held_placed{false};     // x holds the held nodes (placeIterate)
  SamplePositions at_start;    // the points at x_t
  SamplePositions at_x;        // and at x (reset with it)
  std::vector<Contact>* contacts;
  std::vector<std::vector<int>> contact_of;        // per device, sample -> contact or -1
  std::map<std::array<int, 4>, int> pair_contact;  // (device, element, device, element) -> contact
  std::vector<std::vector<int>> lumen_of;  // per inner device, sample -> lumen contact or -1
  std::vector<char> updated;               // per contact: plane already updated in this step
  std::vector<FormedRow> formed;           // per contact: its normal row as last formed
  // The wall's curvature and W's storage:
  std::vector<Band> band;                          // what ws[d].inverse holds
  std::vector<CurvatureTerm> curvature;            // C per device, kept once no longer updated
  std::vector<char> curved;                        // device d steps with A + C
  std::vector<std::vector<ContactRow>> last_rows;  // rows of the last loop that used the band
  std::vector<DelassusBuffer> last_W;              // and its W (reused while the band stays)
  std::vector<VecX> anchor;                        // dq_k: the iterate the loop's QP is about
  std::unique_ptr<pairs::StartAxes> start_axes;    // element pairs: the axes at x_t (on first use)

  /// The lumen contact of sample k of device d, or -1.
  int lumenContactOf(int d, int k) const { return lumen_of[d].empty() ? -1 : lumen_of[d][k]; }
};

/// One loop's linear problem: W lambda + q >= 0 (with friction, the
/// frictional problem with mu), and what the correction needs.
struct LoopSystem {
  int c{0};                                   // contacts
  int m{0};                                   // rows: per contact n (and t1, t2 with friction)
  int kept_rows{0};                           // rows whose entries of W were kept (FormedRow)
  std::vector<const ChainFactor*> factor;     // per device: of A, or of A + C
  std::vector<VecX> dq_step;                  // the loop's free motion (with C)
  std::vector<std::array<Vec3, 2>> tangents;  // per contact with friction: t1, t2
  VecX q, mu;
  MatX W_sum;                                    // m x m, once a device's part is added
  const DelassusBuffer* W_device{nullptr};       // or one device's operator (it holds every row)
  std::unique_ptr<DelassusColumns> columns;      // or W formed as the status method reads it
  std::vector<std::vector<int>> of_device;       // rows with a part on each device
  std::vector<std::vector<ContactRow>> rows_of;  // their rows of H, per device
  std::vector<TrailingSolve> Y;                  // A^-1 H^T where W came from the block solve
  // The lumen's curvature: r rows after the m of the contacts, eliminated
  // from W and q (lumen_curvature.cpp).
  std::vector<LumenSpring> springs;
  VecX e;              // R (dq_k - dq_step) [m]
  MatX W_HR;           // m x r
  Eigen::LLT<MatX> S;  // K^-1 + W_RR
  MatXView W() const { return W_device ? W_device->view() : MatXView(W_sum); }
};

// --- Shared small helpers ---------------------------------------------------

/// Places the loop's iterate: s->x = x_t (+) s->dq for every device (its
/// storage reused), s->at_x reset. The loop changes only the free nodes'
/// increments (the held ones' are the drive's, those of the free motion):
/// once x holds the held nodes, only the free nodes are moved again.
void placeIterate(const ContactProblem& pb, LoopState* s);
/// Which sample points of one device take part in contacts: those that
/// move with a free node and do not lie inside the element cut by a
/// detachment. The device's two numbers are read once for a loop over its
/// points (a call per point that read them through the problem's vectors
/// was 4 % of a coaxial step).
struct TakingPart {
  int first_free_node;
  int cut_element;  // -1: none
  bool operator()(const SamplePoint& s) const {
    if (s.element == cut_element && s.xi > 0.0) return false;
    return s.xi == 0.0 ? s.element >= first_free_node : s.element + 1 >= first_free_node;
  }
};
inline TakingPart takingPart(const ContactProblem& pb, size_t d) {
  return {(*pb.workspaces)[d].first_free_node, (*pb.start)[d].cut_element};
}
/// True when sample point s of device d takes part in contacts (TakingPart).
inline bool takesPart(const ContactProblem& pb, size_t d, const SamplePoint& s) {
  return takingPart(pb, d)(s);
}
/// True for a point of a detached part (a coil cut from its pusher).
bool detached(const DeviceState& x, const SamplePoint& s);
/// Unit tangent of the device axis at a sample point.
Vec3 sampleTangent(const DeviceState& x, const SamplePoint& s);
/// Outer device of device d (-1: none).
int outerOf(const ContactProblem& pb, size_t d);

// --- detection.cpp ----------------------------------------------------------

/// The paper's detection on [x_t, x_f], the wall contacts kept from the last
/// step, device pairs and lumen contacts at x_f; with a predicted first
/// iterate (options.predict_first_iterate) all of it at s->x, the
/// prediction, instead of x_f. *detect_later: the wall's
/// detection waits for the first loop's iterate (options
/// detect_on_first_iterate). Returns true when a point beyond the wall has
/// no plane (stranded: the step cannot be solved).
bool detectOnFreeMotion(const ContactProblem& pb, const ContactOptions& o,
                        fields::SampleFields* field, LoopState* s, bool* detect_later,
                        ContactStats* st);
/// Re-detection at the loop's x: planes of violated contacts updated, new
/// contacts added (wall, pairs, lumen); the deepest point into
/// st->max_penetration_m. `fresh_from`: contacts from this index were added
/// in this loop. Returns true when no point is violated.
bool redetect(const ContactProblem& pb, const ContactOptions& o, fields::SampleFields* field,
              int fresh_from, LoopState* s, ContactStats* st);
/// The converged answer's paths x_t -> x checked for tunnels through a wall
/// into another lumen; each gets the exit's plane. Returns true when none.
bool checkTunnels(const ContactProblem& pb, const ContactOptions& o, fields::SampleFields* field,
                  LoopState* s, ContactStats* st);
/// The paper's detection on [x_t, x], x the loop's iterate s->x (its
/// points from s->at_x), into s->contacts (the first loop after kept
/// contacts). Returns true when a point beyond the wall has no plane.
bool detectWallCrossings(const ContactProblem& pb, const RootOptions& root,
                         fields::SampleFields* field, LoopState* s);

// --- contact_system.cpp -----------------------------------------------------

/// The loop's free motion and factors: A, or A + C with the wall's curvature
/// (C updated in the first curvature_loops loops).
void prepareFreeMotion(const ContactProblem& pb, const ContactOptions& o, int loop, LoopState* s,
                       LoopSystem* sys);

/// The rows of H and q, linearised at x: g(x_f + A^-1 H^T lambda) ~ g(x) +
/// H (x_f - x) + W lambda; then W = H A^-1 H^T per device.
void formContactProblem(const ContactProblem& pb, const ContactOptions& o, LoopState* s,
                        LoopSystem* sys);
/// The first loop's iterate predicted from the last step's contact forces
/// (options.predict_first_iterate): x = x_f + A^-1 H^T f, their forces f
/// (normal and friction) applied at their points at x_t. Returns false
/// (x not placed) when no contact of the last step carried a force.
bool predictFirstIterate(const ContactProblem& pb, LoopState* s);
/// x = x_f (dq = dq_free).
void placeAtFreeMotion(const ContactProblem& pb, LoopState* s);
/// Back to x = x_f with no contacts: the prediction found nothing to hold.
void restartAtFreeMotion(const ContactProblem& pb, LoopState* s);
/// x = x_f + A^-1 H^T lambda; the contacts' forces from lambda.
void correctMotion(const ContactProblem& pb, const LoopSystem& sys, const VecX& lambda,
                   LoopState* s);

// --- lumen_curvature.cpp -----------------------------------------------------

/// The lumen's curvature rows at x of the lumen contacts with a force (none
/// without options.wall_curvature), their parts appended to `parts` as rows
/// m, m + 1, ... and sys->e.
void addLumenSprings(const ContactProblem& pb, const ContactOptions& o, const LoopState& s,
                     LoopSystem* sys, std::vector<std::vector<RowPart>>* parts);
/// Eliminates the springs' rows from W (m + r square, W_sum or W_device) and
/// q: W <- W_HH - W_HR S^-1 W_RH, q <- q + W_HR S^-1 e, S = K^-1 + W_RR.
void eliminateLumenSprings(LoopSystem* sys);
/// The springs' forces for the contacts' lambda: S^-1 (e - W_RH lambda).
VecX lumenSpringForces(const LoopSystem& sys, const VecX& lambda);
/// True when the springs leave no spurious force: each one's slide across
/// the lumen, relative to the outer device, since the QP's anchor is within
/// `settle` of its clearance (options.lumen_settle).
bool lumenSpringsSettled(const LoopSystem& sys, const LoopState& s, double settle);

}  // namespace evsim::activation
