// Anatomical frames. Declared and documented in
// endovascular_sim/geometry/patient_frame.h.
#include "endovascular_sim/geometry/patient_frame.h"

namespace evsim {
namespace {

/// The unit vector toward anatomical direction `toward` (a letter of the
/// code), or toward its opposite `away`; zero when neither is named.
Vec3 direction(const std::string& code, char toward, char away) {
  Vec3 d = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    if (code[k] == toward) d[k] = 1.0;
    if (code[k] == away) d[k] = -1.0;
  }
  return d;
}

}  // namespace

std::string frameCodeProblem(const std::string& code) {
  static const std::string kPairs[3] = {"LR", "AP", "SI"};
  if (code.size() != 3)
    return "'" + code + "' is not an orientation code: three letters, one of each of L/R, A/P, "
           "S/I (e.g. LPS, RAS)";
  for (const std::string& pair : kPairs) {
    int count = 0;
    for (char c : code) count += pair.find(c) != std::string::npos;
    if (count != 1)
      return "'" + code + "' is not an orientation code: it needs one of " + pair.substr(0, 1) +
             "/" + pair.substr(1, 1) + " exactly once (e.g. LPS, RAS)";
  }
  return "";
}

Vec3 posteriorDirection(const std::string& code) { return direction(code, 'P', 'A'); }

Vec3 superiorDirection(const std::string& code) { return direction(code, 'S', 'I'); }

}  // namespace evsim
