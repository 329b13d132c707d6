// Contact resolution within a step (sections 2.2 and 3 of the paper):
//
//   detect    first root of g on [P_t, P_f] for every sample point -> (H_i, delta_i)
//   loop      W = H A^-1 H^T;  W lambda + q >= 0 ⊥ lambda >= 0  (status method)
//             x = x_f + A^-1 H^T lambda
//             re-detect on x: a violated contact's tangent plane is updated
//             from the gradient at x (projection to the surface), a new
//             violation becomes a new contact; a contact violated again after
//             its update gets a second plane (concave walls: updates alone can
//             oscillate, an added plane only shrinks the admissible set)
//   persist   a wall contact that carried a force in the previous step starts
//             this one too, its plane updated at x_t: a pre-shaped tip held
//             against the wall springs back out in the free motion, and
//             without its contact the first loops chase it millimetres away
//   predict   (options.predict_first_iterate) the first loop detects and
//             is linearised at x_f + A^-1 H^T f, f the last step's contact
//             forces at their points at x_t, instead of at x_f: a coil
//             pressed into an aneurysm springs open by half a millimetre in
//             its free motion, and turns found touching only at the first
//             iterate took a loop more; without contacts there, from x_f
//   pairs     with the effect 'device_contact', device points closer than
//             the sum of their radii (same device: more than a few radii
//             apart along it) are pair contacts in the same LCP; between
//             elements (options.element_pairs) a pair that carried a force
//             in the previous step starts this one too, at the same points
//             of the two axes, and pairs get a swept test over the step
//   lumen     with the effect 'coaxial', points of an inner device beyond
//             its outer device's lumen are contacts with the outer axis
//             (contact/coaxial.h), updated and added like wall contacts
//   until     no point lies beyond the wall by more than the tolerance, or
//             N loops (the caller then subdivides the time step).
//
// W is formed per device, A^-1 never: from the band of A^-1
// (mechanics/chain_inverse.h, once a step; for A + C whenever the wall's
// curvature term is updated, options.curvature_loops), in one sweep down
// the chain, where that costs less than the block solve Y = A^-1 H^T with
// the device's chain factor (O(c n) for c rows: a wire touching near its
// tip, or a few rows in the first loop; in the loops after the first the
// band is already there, or serves the loops to come). While the band
// stays, rows unchanged since the last loop keep their entries
// (contact/delassus.h). The correction A^-1 H^T lambda is Y lambda, or one
// solve with the block LDL^T the band came from; A + C of a device with 16
// contacts or more is factorised with its band at once (its free motion
// solved with it), not first as a chain factor alone.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/contact/contact_options.h"
#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/contact/contact_workspace.h"
#include "endovascular_sim/contact/friction.h"
#include "endovascular_sim/contact/lcp.h"
#include "endovascular_sim/core/effect_set.h"
#include "endovascular_sim/core/stage_timer.h"
#include "endovascular_sim/geometry/implicit_surface.h"
#include "endovascular_sim/geometry/interior_ball.h"
#include "endovascular_sim/geometry/root_finding.h"
#include "endovascular_sim/mechanics/implicit_euler.h"

namespace evsim {

/// A contact with the wall (other_device < 0): n . (p - point) >= 0; or
/// between a device point and a point of another device (or of the same
/// one: a coil touching itself): n . (p - p_other) - separation >= 0, with
/// n from the other point to this one and point = the other point when
/// detected. Two device surfaces touching: separation = r + r_other; a point
/// of an inner device in its outer device's lumen (contact/coaxial.h):
/// separation = -(r_lumen - r), the other point on the outer axis and n
/// toward it (contact/coaxial.h).
struct Contact {
  int device{0};
  int sample{0};              // index into the device's sample points
  Vec3 point{Vec3::Zero()};   // on the surface [m]
  Vec3 normal{Vec3::Zero()};  // unit, into the free space: the tangent plane
  double gap{0.0};            // n . (p - point) at the end of the step [m]
  double force{0.0};          // lambda [N]
  int other_device{-1};       // pair contacts: the other point
  int other_sample{-1};
  Vec3 friction{Vec3::Zero()};  // tangential force on the device point [N] (effect 'friction')
  SamplePoint other{};          // the other device's point (its element, xi, radius, mu)
  SamplePoint self{};           // pair contacts: this device's point (the closest point of its
                                // element's axis; `sample` is that element's first sample)
  double separation{0.0};       // [m], see above
  bool lumen{false};            // an inner device's point in its outer device's lumen
};

/// The device's point of a contact: for a device pair the closest point of
/// its element's axis, else its sample point.
inline const SamplePoint& contactPointOf(const Contact& c,
                                         const std::vector<std::vector<SamplePoint>>& samples) {
  return c.other_device >= 0 && !c.lumen ? c.self : samples[c.device][c.sample];
}

/// Rows the activation loop added after its first LCP (each cost a loop):
/// wall planes (new crossings and second planes, tunnels), device pairs,
/// an inner device's points beyond its outer device's lumen.
struct LateRows {
  int wall{0};
  int pair{0};
  int lumen{0};
  LateRows& operator+=(const LateRows& o) {
    wall += o.wall, pair += o.pair, lumen += o.lumen;
    return *this;
  }
};

/// Wall time of the contact stages [ms]. The first five are consecutive
/// stages of the step's clock (StageTimer); the last two are parts of
/// detection_ms.
struct ContactTimes {
  double detection_ms{0.0};       // first roots, re-detection, plane updates, tunnel checks
  double curvature_ms{0.0};       // the wall curvature term: A + C, its factor and step
  double delassus_ms{0.0};        // W = H A^-1 H^T (q, H with it)
  double lcp_ms{0.0};             // the status method (or the chosen solver)
  double correction_ms{0.0};      // x = x_f + A^-1 H^T lambda
  double device_contact_ms{0.0};  // effect 'device_contact': pair detection
  double coaxial_ms{0.0};         // effect 'coaxial': lumen detection

  ContactTimes& operator+=(const ContactTimes& o);
  /// The consecutive stages' sum (without the parts of detection_ms).
  double stagesMs() const {
    return detection_ms + curvature_ms + delassus_ms + lcp_ms + correction_ms;
  }
};

/// What one contact resolution found, and (in StepStats) a step's over its
/// accepted sub-steps (addSubStep).
struct ContactStats {
  int contacts{0};                   // rows of the last LCP
  int active_contacts{0};            // with a positive force
  int sliding_contacts{0};           // effect 'friction': on the cone's boundary
  int friction_solves{0};            // frictional problems solved (effect 'friction')
  int activation_loops{0};           // of the resolution (a step's: the most of its sub-steps)
  int lcp_iterations{0};             // summed over the loops (and sub-steps)
  double lcp_residual{0.0};          // natural-map residual of the last LCP (step: worst)
  double max_penetration_m{0.0};     // deepest sample point beyond the wall at the end [m]
                                     // (infinite: outside the vessel tree)
  int deepest_device{-1};            // that point's device (-1: none beyond)
  Vec3 deepest_point{Vec3::Zero()};  // and position [m]
  LcpStatus lcp_status{LcpStatus::kSolved};  // not kSolved: the loop stopped at a failed LCP, or
                                             // ended on an unsolved one (lcp.h)
  int tunnels{0};  // loop iterates inside a vessel whose path from x_t crossed a wall, re-solved
  int pair_passes{0};      // device-pair detection passes (effect 'device_contact')
  int lumen_passes{0};     // coaxial lumen detection passes (effect 'coaxial')
  int on_demand_loops{0};  // loops whose W was formed column by column (columns_on_demand)
  int kept_rows{0};  // rows whose entries of W a loop kept from the last (contact.row_turn), summed
  int slid_forces{0};  // forces a new pair took over as its warm start (slid_pair_warm_start)
  int first_rows{0};   // rows of the first loop's LCP
  LateRows late_rows;  // rows the loop added after its first LCP, by kind (step: summed)
  ContactTimes times;  // of every attempt, a rejected one too (its cost is real)

  /// Adds an accepted sub-step's results (not its times): counts summed,
  /// loops and residual their worst, the rest the last sub-step's.
  void addSubStep(const ContactStats& sub);
};

/// The LCP of the last activation loop (for dumps and offline comparisons).
/// With the effect 'friction' every contact has three rows (n, t1, t2):
/// the problem is Siconos' fc3d with coefficients mu.
struct LcpRecord {
  MatX W;   // c x c (3c x 3c) Delassus operator [m/N]
  VecX q;   // gaps after the free motion (and free slips) [m]
  VecX z;   // forces found [N]
  VecX mu;  // per contact, friction only
};

/// Writes a record as text: a header comment, "size c", then "W" and its c
/// rows, "q" and c numbers, "z" and c numbers (%.17g); with friction then
/// "mu c/3" and the coefficients. Returns false on I/O failure.
bool writeLcpRecord(const LcpRecord& record, const std::string& path);
/// Reads a record written by writeLcpRecord (throws LoadError).
LcpRecord readLcpRecord(const std::string& path);

/// One contact problem: states at the start of the step, free-motion
/// increments and factors in the workspaces (corrected in place).
struct ContactProblem {
  const std::vector<DeviceModel>* devices{nullptr};
  const std::vector<DeviceState>* start{nullptr};  // x_t (drive already advanced)
  EffectSet effects;  // the scene's: 'friction' and 'device_contact' change the problem
  std::vector<DeviceWorkspace>* workspaces{nullptr};
  ContactWorkspace* kept{nullptr};  // what the solver keeps for this simulation (nullptr: a call
                                    // that keeps nothing, as the first of a simulation would find)
  const std::vector<std::vector<SamplePoint>>* samples{nullptr};
  const ImplicitSurface* surface{nullptr};
  MotionSnapshot motion;       // of the surface at the end of the step
  LcpRecord* record{nullptr};  // when set, receives the last LCP
  /// Contacts of the previous step: a wall contact that carried a force
  /// starts this step as a contact again, its tangent plane updated where its
  /// point now projects on the wall (null or empty: detection alone).
  const std::vector<Contact>* previous{nullptr};
  /// Effect 'coaxial': per device, the device whose lumen it runs in (-1:
  /// none). Null or empty: no coaxial devices.
  const std::vector<int>* outer_of{nullptr};
  /// Per device and sample point, the certified interior ball of its last
  /// evaluation (geometry/interior_ball.h), kept across steps (null: kept
  /// for the step's loops only); on a moving surface it follows the motion.
  std::vector<std::vector<InteriorBall>>* interior{nullptr};
  /// When set, receives x_t (+) the step's dq, the configuration the loop
  /// ended at (what commitMotion makes of *start with each workspace's dq,
  /// to the bit): the caller need not move the devices again. What it held
  /// before serves as storage for the loop's iterates.
  std::vector<DeviceState>* end{nullptr};
};

/// Two device elements that overlap: sample points of theirs closer than
/// the sum of their radii, as the effect 'device_contact' sees them (two
/// devices, or one device with itself more than a few radii apart along
/// it; an inner device in its outer device's lumen is no pair).
struct DeviceOverlap {
  int device_a, element_a;
  int device_b, element_b;
  double depth;  // sum of the radii minus the points' distance [m]
};

/// The overlaps deeper than `tolerance` [m] in the configuration
/// problem.start (workspaces' first_free_node set): per pair of elements
/// the deepest, deepest first. A scene whose devices start so is refused
/// at load (sim/scene_model.cpp): its first step would have to push them
/// apart by that much. Pairs as the scene's contact.element_pairs finds them.
std::vector<DeviceOverlap> deviceOverlaps(const ContactProblem& problem, double tolerance,
                                          bool element_pairs = false);

/// Corrects ws.dq of every device so that no sample point lies beyond the
/// surface by more than the tolerance. Returns false when that was not
/// reached in max_activation_loops (contacts and stats still describe the
/// last loop). The stages' times go to stats->times, measured on *timer
/// when given (the step's clock: the time between stages to its remainder).
bool resolveContacts(const ContactProblem& problem, const ContactOptions& options,
                     std::vector<Contact>* contacts, ContactStats* stats,
                     StageTimer* timer = nullptr);

}  // namespace evsim
