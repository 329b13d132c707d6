// The contact solver's user-facing options, one row each
// (contact/contact_options.h): the scene format, the loader and the range
// check read this table; the defaults are ContactOptions{}'s.
#include "endovascular_sim/contact/contact_options.h"

#include <cmath>
#include <type_traits>

#include "endovascular_sim/core/number_text.h"

namespace evsim {
namespace {

template <typename T>
double toNumber(T v) {
  if constexpr (std::is_enum_v<T>)
    return static_cast<double>(static_cast<int>(v));
  else
    return static_cast<double>(v);
}

template <typename T>
void assign(T* member, double v) {
  if constexpr (std::is_enum_v<T>)
    *member = static_cast<T>(static_cast<int>(v));
  else if constexpr (std::is_same_v<T, bool>)
    *member = v != 0.0;
  else
    *member = static_cast<T>(v);
}

/// A row of the table, built by chained calls (as the scene schema's).
struct Field {
  ContactOptionField f;
  Field(const char* key, OptionType type, const char* meaning, double (*get)(const ContactOptions&),
        void (*set)(ContactOptions*, double)) {
    f.key = key;
    f.type = type;
    f.meaning = meaning;
    f.get = get;
    f.set = set;
  }
  Field& unit(const char* u) { return f.unit = u, *this; }
  /// Bounds: "[]", "(]", "[)" or "()" say which ends are open.
  Field& in(const char* ends, double lo, double hi) {
    f.min = lo, f.max = hi, f.min_open = ends[0] == '(', f.max_open = ends[1] == ')';
    return *this;
  }
  Field& choices(std::vector<std::string> c) { return f.choices = std::move(c), *this; }
  operator ContactOptionField() const { return f; }  // NOLINT: the table's rows
};

// The getter and setter of a member of ContactOptions.
#define EVSIM_MEMBER(m)                                  \
  [](const ContactOptions& o) { return toNumber(o.m); }, \
      [](ContactOptions* o, double v) { assign(&o->m, v); }

std::vector<ContactOptionField> makeFields() {
  using T = OptionType;
  const std::vector<std::string> lcp_solvers = {lcpSolverName(LcpSolver::kStatusMethod),
                                                lcpSolverName(LcpSolver::kPgs),
                                                lcpSolverName(LcpSolver::kLemke)};
  const std::vector<std::string> friction_solvers = {frictionSolverName(FrictionSolver::kNewton),
                                                     frictionSolverName(FrictionSolver::kNsgs)};
  return {
      Field("solver", T::kChoice, "the LCP solver", EVSIM_MEMBER(lcp.solver)).choices(lcp_solvers),
      Field("tolerance", T::kNumber, "LCP: w >= -tolerance", EVSIM_MEMBER(lcp.tolerance))
          .unit("m")
          .in("(]", 0, 1e-3),
      Field("max_iterations", T::kInteger, "pivots or sweeps (0: automatic)",
            EVSIM_MEMBER(lcp.max_iterations))
          .in("[]", 0, 1e6),
      Field("max_activation_loops", T::kInteger, "loops of the activation; then the step is halved",
            EVSIM_MEMBER(max_activation_loops))
          .in("[]", 1, 1000),
      Field("max_subdivisions", T::kInteger, "halvings of a step (4: down to dt / 16)",
            EVSIM_MEMBER(max_subdivisions))
          .in("[]", 0, 12),
      Field("contact_spacing", T::kNumber, "sample points along the elements",
            EVSIM_MEMBER(contact_spacing))
          .unit("m")
          .in("[]", 1e-5, 0.05),
      Field("penetration_tolerance", T::kNumber, "a point beyond the wall by more is violated",
            EVSIM_MEMBER(penetration_tolerance))
          .unit("m")
          .in("[]", 1e-9, 1e-3),
      Field("keep_gap", T::kNumber,
            "a wall contact that ended the last step without force at most this far from its "
            "plane starts the next (at least penetration_tolerance; about the wall's travel in a "
            "step where vessels move)",
            EVSIM_MEMBER(keep_gap))
          .unit("m")
          .in("[]", 0.0, 1e-3),
      Field("pair_tolerance", T::kNumber,
            "effect 'device_contact': two device surfaces that overlap by more are violated (at "
            "least penetration_tolerance; docs/performance.md)",
            EVSIM_MEMBER(pair_tolerance))
          .unit("m")
          .in("[]", 0.0, 1e-4),
      Field("new_pair_overlap", T::kNumber,
            "effect 'device_contact': a device pair not held in the last step becomes a contact "
            "in the step's first detection once its surfaces overlap by more than this (0: once "
            "they touch; later loops: pair_tolerance; docs/performance.md)",
            EVSIM_MEMBER(new_pair_overlap))
          .unit("m")
          .in("[]", 0.0, 1e-4),
      Field("root_tolerance", T::kNumber, "the first root's position", EVSIM_MEMBER(root.tolerance))
          .unit("m")
          .in("(]", 0, 1e-6),
      Field("wall_curvature", T::kBool,
            "the wall's curvature in the activation loop (docs/model.md)",
            EVSIM_MEMBER(wall_curvature)),
      Field("curvature_loops", T::kInteger, "loops that update the curvature term",
            EVSIM_MEMBER(curvature_loops))
          .in("[]", 1, 1000),
      Field("predict_first_iterate", T::kBool,
            "the first loop detects and linearises at the free motion moved by the last step's "
            "contact forces, not at the free motion (docs/model.md)",
            EVSIM_MEMBER(predict_first_iterate)),
      Field("element_pairs", T::kBool,
            "effect 'device_contact': pairs between the elements' axes, at their closest points, "
            "with a swept test over each step (false: between sample points; docs/model.md)",
            EVSIM_MEMBER(element_pairs)),
      Field("lumen_tolerance", T::kNumber,
            "effect 'coaxial': a point beyond its outer device's lumen by more is violated",
            EVSIM_MEMBER(lumen_tolerance))
          .unit("m")
          .in("[]", 1e-9, 1e-3),
      Field("lumen_settle", T::kNumber,
            "effect 'coaxial': the loop goes on while a point held by the lumen's curvature slid "
            "more than this fraction of the clearance",
            EVSIM_MEMBER(lumen_settle))
          .in("[]", 1e-4, 1),
      Field("friction_solver", T::kChoice, "effect 'friction': the solver",
            EVSIM_MEMBER(friction_solver.solver))
          .choices(friction_solvers),
      Field("friction_tolerance", T::kNumber, "Siconos' fc3d error",
            EVSIM_MEMBER(friction_solver.tolerance))
          .in("(]", 0, 1e-2),
  };
}

#undef EVSIM_MEMBER

/// Ranges of the internal options (not scene keys: ContactOptions' last
/// members, and the solvers' own limits), checked as the table's are.
struct InternalRange {
  const char* name;
  double value, min, max;
  bool min_open;
  const char* unit;
};

}  // namespace

const std::vector<ContactOptionField>& contactOptionFields() {
  static const std::vector<ContactOptionField> fields = makeFields();
  return fields;
}

const ContactOptionField* findContactOption(const std::string& key) {
  for (const ContactOptionField& f : contactOptionFields())
    if (f.key == key) return &f;
  return nullptr;
}

std::string formatContactOption(const ContactOptionField& field, const ContactOptions& options) {
  const double v = field.get(options);
  switch (field.type) {
    case OptionType::kBool:
      return v != 0.0 ? "true" : "false";
    case OptionType::kChoice:
      return field.choices.at(static_cast<size_t>(v));
    default:
      return numberText(v);
  }
}

std::string contactOptionRange(const ContactOptionField& field) {
  if (field.type == OptionType::kBool) return "true or false";
  if (field.type == OptionType::kChoice) {
    std::string names;
    for (const std::string& c : field.choices) names += (names.empty() ? "" : ", ") + c;
    return "one of " + names;
  }
  return rangeText(field.min, field.max, field.min_open, field.max_open, field.unit);
}

std::string validateContactOptions(const ContactOptions& o) {
  for (const ContactOptionField& f : contactOptionFields()) {
    const double v = f.get(o);
    const bool whole = f.type != OptionType::kNumber;
    const double top = f.type == OptionType::kBool     ? 1.0
                       : f.type == OptionType::kChoice ? f.choices.size() - 1.0
                                                       : f.max;
    const double bottom = whole && f.type != OptionType::kInteger ? 0.0 : f.min;
    if (!inRange(v, bottom, top, f.min_open && !whole, f.max_open && !whole) ||
        (whole && v != std::floor(v)))
      return "contact." + f.key + " must " +
             (f.type == OptionType::kNumber || f.type == OptionType::kInteger ? "lie in " : "be ") +
             contactOptionRange(f) + ", got " + numberText(v);
  }
  const InternalRange internal[] = {
      {"row_turn", o.row_turn, 0.0, 0.1, false, "rad"},
      {"lcp regularization", o.lcp.regularization, 0.0, 1e-3, false, ""},
      {"friction max_sweeps", static_cast<double>(o.friction_solver.max_sweeps), 1.0, 1e6, false,
       ""},
  };
  for (const InternalRange& r : internal)
    if (!inRange(r.value, r.min, r.max, r.min_open, false))
      return std::string(r.name) + " must lie in " +
             rangeText(r.min, r.max, r.min_open, false, r.unit) + ", got " + numberText(r.value);
  return "";
}

}  // namespace evsim
