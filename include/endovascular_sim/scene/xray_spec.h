// The X-ray system of a scene (key `xray:`): a C-arm posed the way
// clinicians pose it, the beam, the contrast agent and the detector's
// noise. Plain data; the imaging layer renders with it (imaging/).
#pragma once

#include <string>

#include "endovascular_sim/core/types.h"

namespace evsim {

/// A C-arm around the patient. At LAO 0 and cranial 0 (the AP view) the
/// source is behind the patient (posterior) and the detector in front;
/// the image shows the patient's right on its left and the head up, as
/// clinicians read it. LAO turns the detector towards the patient's left
/// (RAO: negative), cranial tilts it towards the head (caudal: negative).
struct CArmSpec {
  double lao{0.0};                        // [rad] LAO > 0, RAO < 0, within [-pi/2, pi/2]
  double cranial{0.0};                    // [rad] cranial > 0, caudal < 0, within [-pi/3, pi/3]
  double source_detector_distance{1.2};   // SID [m]
  double source_isocenter_distance{0.8};  // source to the rotation centre (patient) [m]
  double detector_size{0.3};              // side of the square detector [m]
  int pixels{512};                        // per side
  bool isocenter_given{false};            // else the centre of the vessels' bounds
  Vec3 isocenter{Vec3::Zero()};           // [m] in the scene frame
  Vec3 left{1.0, 0.0, 0.0};               // the patient's left, in the scene frame
  Vec3 anterior{0.0, 1.0, 0.0};           // the patient's front (superior = left x anterior)
};

/// Why a C-arm pose cannot image ("" when it can).
std::string validateCArm(const CArmSpec& c);

/// The spine, the landmark clinicians place the C-arm by: a column of
/// vertebral bodies (cylinders of bone along the superior axis, with discs
/// between them) through `center`.
struct SpineSpec {
  bool present{false};
  Vec3 center{Vec3::Zero()};  // [m] a point on its axis, in the scene frame
  double radius{0.02};        // [m] of a vertebral body
  double vertebra{0.025};     // [m] height of a body
  double disc{0.005};         // [m] height of a disc between two
  double bone_fraction{0.3};  // of a body's volume that is cortical bone (the rest marrow)
};

struct XraySpec {
  bool present{false};  // the scene has an `xray:` section
  CArmSpec c_arm;
  double energy_kev{60.0};             // effective beam energy [keV], in [35, 120]
  double frame_rate{15.0};             // [1/s]: 7.5, 15 and 30 are the usual ones
  double iodine_concentration{150.0};  // [kg/m^3] (mg/mL) in the filled blood
  double contrast_washout{1.0};        // [s] for the iodine to clear after an injection
  double body_width{0.32};             // [m] soft tissue: an elliptic cylinder along the
  double body_depth{0.22};             // [m] superior axis through the isocentre
  double photons{0.0};                 // quanta per pixel behind the body (Poisson noise); 0 off
  double blur{0.0};                    // [px] Gaussian sigma of the detector's blur; 0 off
  unsigned seed{1};                    // of the noise
  SpineSpec spine;                     // none unless given
  int supersampling{2};  // rays per pixel along each side through the devices, 1..8: the
                         // detector integrates over a pixel, and a wire is about a pixel wide
                         // (the body and the lumen, smooth at that scale: one ray)
};

/// Why an X-ray system is out of range ("" when valid).
std::string validateXray(const XraySpec& x);

}  // namespace evsim
