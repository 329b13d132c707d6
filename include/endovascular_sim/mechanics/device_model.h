// A flexible device (guidewire, catheter, coil) as a chain of beam elements:
// its description, and the immutable model built from it.
//
// Material coordinate s runs from the proximal end (s = 0) to the distal tip
// (s = length). Rest nodal frames have their x axis along the device.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/mechanics/beam_element.h"
#include "endovascular_sim/mechanics/beam_section.h"
#include "endovascular_sim/mechanics/radiopacity.h"

namespace evsim {

/// One section of uniform material and rest curvature (a URDF link).
struct DeviceSectionSpec {
  std::string name;
  BeamSection section;
  double length{0.0};                  // [m]
  int elements{0};                     // beam elements in this section
  Vec3 rest_curvature{0.0, 0.0, 0.0};  // (twist, bend y, bend z) [1/m]
  double friction{0.0};                // Coulomb coefficient on its surface [-]
  double lumen_friction{0.0};          // on its lumen's wall (a device inside it) [-]
  int xray_material{-1};               // index into xrayMaterials(); -1: kDefaultXrayMaterial
  double xray_fill{1.0};               // volume fraction of the cross-section the material fills (a
                                       // coil's winding) [-], in (0, 1]
};

/// A radiopaque band as a device file places it: on a section, from its start.
struct XrayMarkerSpec {
  int section{0};        // index into DeviceSpec::sections
  double position{0.0};  // [m] from the section's proximal end to the band's start
  double length{0.0};    // [m]
  int material{-1};      // index into xrayMaterials()
};

/// What a hand's drive applies at most where neither the device file nor
/// the scene says (docs/model.md, "Drive limits"): the force at which a
/// 0.014 in guidewire pushed by hand crosses an occlusion's fibrous cap and
/// buckles, and the torque at which a 0.36 mm nitinol wire's surface reaches
/// the superelastic plateau in shear (650 MPa / sqrt(3) * pi d^3 / 16).
inline constexpr double kDefaultDriveMaxForce = 1.5;      // [N]
inline constexpr double kDefaultDriveMaxTorque = 3.3e-3;  // [N m]

/// What the device file says: sections from proximal to distal end, limits.
struct DeviceSpec {
  std::string name;
  std::vector<DeviceSectionSpec> sections;
  double max_insertion_speed{0.05};   // [m/s]
  double max_rotation_speed{6.2832};  // [rad/s]
  /// The drive's limits a scene applies unless it gives its own.
  double drive_max_force{kDefaultDriveMaxForce};    // [N]
  double drive_max_torque{kDefaultDriveMaxTorque};  // [N m]
  double rayleigh_mass{0.0};                        // alpha in D = alpha M + beta K [1/s]
  double rayleigh_stiffness{0.0};                   // beta [s]
  std::string detach_section;           // a coil: the section that detaches on command ("": none)
  std::vector<XrayMarkerSpec> markers;  // radiopaque bands
};

struct DeviceModel {
  std::string name;
  double length{0.0};  // [m]
  int num_nodes{0};
  std::vector<double> node_s;             // material coordinate (nodes) [m]
  std::vector<BeamElementRest> elements;  // element e joins nodes e and e+1
  std::vector<int> element_section;       // section index of each element
  std::vector<double> node_mass;          // lumped translational mass [kg]
  std::vector<Vec3> node_inertia;         // lumped body inertia (Jx, Iy, Iz) [kg m^2]
  std::vector<double> node_radius;        // outer radius [m]
  std::vector<Vec3> rest_position;        // rest shape, proximal frame at origin [m]
  std::vector<Mat3> rest_rotation;
  std::vector<double> rest_twist;  // integral of rest twist from s = 0 [rad]
  std::vector<std::string> section_names;
  std::vector<double> section_friction;        // Coulomb coefficient per section [-]
  std::vector<double> section_lumen_radius;    // inner radius per section, 0: solid [m]
  std::vector<double> section_lumen_friction;  // Coulomb coefficient of the lumen wall [-]
  std::vector<int> section_xray_material;      // index into xrayMaterials() per section
  std::vector<double> section_xray_fill;       // volume fraction per section [-]
  std::vector<XrayMarker> xray_markers;        // radiopaque bands, by material coordinate
  double max_insertion_speed{0.0};             // [m/s]
  double max_rotation_speed{0.0};              // [rad/s]
  double rayleigh_mass{0.0};                   // [1/s]
  double rayleigh_stiffness{0.0};              // [s]
  // Effect 'blood_drag' (mechanics/blood_drag.h), per node; empty: none. Slender-body
  // drag across and along [N s/m]; the cylinder's form drag 1/2 rho d times the node's
  // length [kg/m] and rho d / mu [s/m] (its Reynolds number per unit speed).
  std::vector<double> node_drag_across, node_drag_along;
  std::vector<double> node_drag_form, node_drag_reynolds;
  int detach_element{-1};  // cut on detach: the last element before detach_section (-1: none)
};

/// Discretises the sections into elements and integrates the rest shape.
/// Throws std::invalid_argument on an inconsistent spec (checked by loaders
/// first, so that their errors name the file).
DeviceModel buildDeviceModel(const DeviceSpec& spec);

/// Uniform straight device of one section (tests, benchmarks).
DeviceSpec straightDeviceSpec(const std::string& name, const BeamSection& section, double length,
                              int elements);

}  // namespace evsim
