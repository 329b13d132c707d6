// The contact solver's options, described once. ContactOptions holds them
// (its member initialisers are the defaults); contactOptionFields() lists
// the user-facing ones: key under a scene's `contact:`, type, unit, range and
// meaning, and where each lives in ContactOptions. The scene format's rows
// (scene/scene_schema.cpp), the loader's reader (scene/scene_file.cpp) and
// validateContactOptions are all driven by that list, so a key is added,
// renamed or re-ranged in one place.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/contact/friction.h"
#include "endovascular_sim/contact/lcp.h"
#include "endovascular_sim/geometry/root_finding.h"

namespace evsim {

struct ContactOptions {
  LcpOptions lcp;                      // solver, tolerance, iteration limit
  int max_activation_loops{10};        // N: then the step is subdivided
  int max_subdivisions{4};             // recursive halvings of a step (dt / 16)
  double contact_spacing{1e-3};        // sample points along elements [m]
  double penetration_tolerance{1e-6};  // a point beyond the wall by more is violated [m]
  double keep_gap{0.0};  // a wall contact of the last step that ended without force at most this
                         // far from its plane (and at least penetration_tolerance) starts the
                         // next step [m]: about the wall's travel in a step where vessels move
  RootOptions root;      // first-root search
  bool element_pairs{false};          // device pairs between elements' axes, not sample points
  bool wall_curvature{true};          // the wall's curvature in A (contact/wall_curvature.h)
  int curvature_loops{1000};          // loops that update C (then A + C and its band are kept)
  bool predict_first_iterate{false};  // detect and linearise the first loop at x_f + A^-1 H^T f,
                                      // f the last step's contact forces, not at x_f
  double pair_tolerance{0.0};         // effect 'device_contact': two device surfaces that overlap
                                      // by more are violated (at least penetration_tolerance) [m]
  double new_pair_overlap{0.0};       // effect 'device_contact': a pair not held in the last
                                      // step is a contact of the first detection once it overlaps
                                      // by more (0: once it touches; later: pair_tolerance) [m]
  double lumen_tolerance{5e-6};       // effect 'coaxial': a point of an inner device beyond its
                                      // outer device's lumen by more is violated [m]
  double lumen_settle{0.1};  // effect 'coaxial': the loop goes on while a point held by the
                             // lumen's curvature slid more than this fraction of the clearance
                             // since the loop's anchor: what that leaves is a force below this
                             // fraction of the contact's (docs/model.md, "Coaxial devices") [-]
  FrictionOptions friction_solver;  // its tolerance and sweep limit

  // Internal, not scene keys (retiredSceneKeys, scene/scene_schema.h):
  // either setting gives the same answer, or the setting is the solver's own
  // business; their tests compare the settings. The faster one is the
  // default and the only one scenes get.
  bool interior_balls{true};           // spare evaluations in certified balls (sample_fields.h)
  bool detect_on_first_iterate{true};  // with kept contacts, detect on x_t -> x_1, not -> x_f
  bool columns_on_demand{true};        // frictionless status method: W's columns formed as it reads
                                       // them, not the whole W (contact/delassus_columns.h)
  bool slid_pair_warm_start{true};     // element pairs: a new pair of the first detection next
                                       // to a pair kept from the last step with a force takes that
                                       // force over as the LCP's warm start (pair_detection.h)
  double row_turn{2e-2};  // a contact's normal row of H is formed again at the loop's x once a
                          // node tangent of its element turned by more since it was formed (0:
                          // every loop; its W entries are kept while it is not) [rad]
};

enum class OptionType { kNumber, kInteger, kBool, kChoice };

/// A user-facing contact option: a scene key under `contact:`.
struct ContactOptionField {
  std::string key;  // "tolerance"
  OptionType type{OptionType::kNumber};
  std::string unit;  // "m", "rad", "" for none
  double min{0.0}, max{0.0};
  bool min_open{false}, max_open{false};  // (min, ...] or [..., max)
  std::vector<std::string> choices;       // kChoice: the names, in the enumeration's order
  std::string meaning;
  double (*get)(const ContactOptions&){nullptr};  // a bool as 0 or 1, a choice as its index
  void (*set)(ContactOptions*, double){nullptr};
};

/// The user-facing options, in the scene reference's order.
const std::vector<ContactOptionField>& contactOptionFields();

/// The option of scene key `key` ("tolerance"), or nullptr.
const ContactOptionField* findContactOption(const std::string& key);

/// The option's value in `options` as a scene writes it: "1e-6", "0.001",
/// "10", "true", "status".
std::string formatContactOption(const ContactOptionField& field, const ContactOptions& options);

/// The option's range as the reference writes it: "(0, 0.001] m".
std::string contactOptionRange(const ContactOptionField& field);

/// Why the options are out of range ("" when they are valid): the first
/// option outside its range, by its scene key.
std::string validateContactOptions(const ContactOptions& options);

}  // namespace evsim
