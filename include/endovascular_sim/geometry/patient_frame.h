// The anatomical frame of a vessel file: which way each axis points in the
// patient, as a three-letter orientation code (DICOM and ITK: "LPS", 3D
// Slicer: "RAS"). Letter k names where +axis k points: L or R (the
// patient's left or right), A or P (anterior, posterior), S or I
// (superior, inferior). The shipped vessels are "LAS": x toward the
// patient's left, y anterior, z superior.
#pragma once

#include <string>

#include "endovascular_sim/core/types.h"

namespace evsim {

/// Why `code` is not an orientation code ("" when it is): three letters,
/// one of each pair L/R, A/P, S/I, in any order.
std::string frameCodeProblem(const std::string& code);

/// The unit vector toward the patient's posterior (the table, for a
/// patient lying supine) in a frame of a valid code.
Vec3 posteriorDirection(const std::string& code);

/// The unit vector toward the patient's head.
Vec3 superiorDirection(const std::string& code);

}  // namespace evsim
