// Device files: URDF (read with urdfdom) plus an endovascular_sim extension.
//
// Sections are URDF links chained by fixed joints from the proximal (root) to
// the distal link. A link gives the section's outer radius and length (its
// <collision> or <visual> <cylinder>) and its mass (<inertial><mass>, from
// which the density follows). What URDF lacks is given by top-level elements,
// ignored by other URDF tools:
//
//   <evsim_device max_insertion_speed="0.05"   [m/s]
//                 max_rotation_speed="6.28"    [rad/s]
//                 rayleigh_mass="1.0"          [1/s]  (optional, default 0)
//                 rayleigh_stiffness="0"       [s]    (optional, default 0)
//                 drive_max_force="1.5"        [N]    (optional, kDefaultDriveMaxForce)
//                 drive_max_torque="0.0033"/>  [N m]  (optional, kDefaultDriveMaxTorque)
//   <evsim_section link="tip"
//                  young_modulus="4e10"        [Pa]
//                  poisson_ratio="0.33"        [-]   (or shear_modulus [Pa])
//                  inner_radius="0"            [m]   (optional, default 0)
//                  elements="20"               [-]
//                  rest_curvature="0 0 157"/>  (twist, bend y, bend z) [1/m]
//                                              (optional, default straight)
// Every link needs one <evsim_section>. See config/devices/README.md.
#pragma once

#include <string>

#include "endovascular_sim/mechanics/device_model.h"

namespace evsim {

/// Reads and validates a device file. Throws LoadError naming the file, the
/// line and the field of the first problem found.
DeviceSpec loadDeviceFile(const std::string& path);

}  // namespace evsim
