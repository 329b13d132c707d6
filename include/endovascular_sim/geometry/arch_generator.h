// Aortic arches drawn from published anatomical statistics, with a seed:
// the arch types I-III (how far below the arch's apex the brachiocephalic
// trunk arises, in left common carotid diameters), the bovine arch (the
// left common carotid from the brachiocephalic trunk), the aberrant right
// subclavian (arteria lusoria: from the distal arch, behind the others),
// elongation, the branches' take-off angles, ostia spacing and radii. What
// stEVE's ArchVariety draws for its agents, here as a centreline with radii
// and named vessels that goes through the same patient path as a real one
// (scene/centerline_vtk_writer.h writes it as VMTK does). The frame is the
// shipped vessels' (patient_frame.h: LAS, x left, y anterior, z superior);
// sources of every range in docs/patient_anatomy.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "endovascular_sim/geometry/centerline.h"

namespace evsim {

enum class ArchType { kI = 1, kII = 2, kIII = 3 };

/// What the draw may give: -1 / 0 / 1 per variant for "drawn with its
/// population frequency" / "never" / "always".
struct ArchDrawOptions {
  int type{0};           // 0: drawn (I 60 %, II 28 %, III 12 %), else 1-3
  int bovine{-1};        // common origin of the brachiocephalic trunk and left common carotid
  int aberrant_rsa{-1};  // aberrant right subclavian artery
  double elongation{-1.0};  // arch height over width factor in [0, 1] (-1: drawn; older: higher)
};

/// One arch's parameters; lengths [m], angles [rad].
struct ArchParameters {
  std::uint64_t seed{0};
  ArchType type{ArchType::kI};
  bool bovine{false};
  bool aberrant_rsa{false};
  double elongation{0.0};      // [0, 1]
  double width{0.05};          // between the ascending and descending aorta's axes
  double depth{0.035};         // anterior-posterior spread of the arch
  double height{0.03};         // of the arch's apex over the ascending aorta's top
  double trunk_drop{0.005};    // the brachiocephalic trunk's origin below the apex
  double radius_ascending{0.015}, radius_arch{0.013}, radius_descending{0.011};
  double radius_trunk{0.0065}, radius_rcca{0.0035}, radius_lcca{0.0035};
  double radius_rsa{0.0045}, radius_lsa{0.0048};
  double gap_trunk_lcca{0.004};  // wall to wall along the arch between their ostia
  double gap_lcca_lsa{0.006};
  double trunk_length{0.04};
  double takeoff_trunk{0.0}, takeoff_lcca{0.0}, takeoff_lsa{0.0};  // tilt from the mean [rad]
  std::string summary() const;  // "type II, bovine, elongation 0.4, ..."
};

/// Draws an arch's parameters from the statistics (deterministic in seed).
ArchParameters drawArch(std::uint64_t seed, const ArchDrawOptions& options = {});

/// The arch as a centreline: ascending aorta (the root), aortic_arch,
/// descending_aorta (to the femoral side), brachiocephalic_trunk (unless
/// aberrant), right_subclavian, right_common_carotid, left_common_carotid,
/// left_subclavian; points about every millimetre, frame LAS.
Centerline archCenterline(const ArchParameters& p);

/// The five targets of an arch's navigation: the trunk (when there is one),
/// both common carotids, both subclavians.
std::vector<std::string> archTargets(const ArchParameters& p);

/// The catheter a clinician takes from the femoral access for `target` in
/// this arch: "catheter" (45 degrees: the left side of type I and II
/// arches, an aberrant right subclavian), "headhunter" (the trunk's side, a
/// bovine left carotid, the left carotid of a type III arch; a clinician
/// takes a Simmons curve there in type III, whose technique the autopilot
/// does not know).
std::string archCatheter(const ArchParameters& p, const std::string& target);

}  // namespace evsim
