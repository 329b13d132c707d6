// A straight one-section wire as a URDF device file, for tests that build
// their scene in a temporary folder.
#pragma once

#include <sstream>
#include <string>

namespace evsim {
namespace test {

/// mass [kg], radius and length [m], Young's modulus [Pa], elements.
inline std::string wireUrdf(double mass, double radius, double length, double young_modulus,
                            int elements) {
  std::ostringstream s;
  s << "<?xml version=\"1.0\"?>\n<robot name=\"wire\">\n  <link name=\"shaft\">\n"
    << "    <inertial><mass value=\"" << mass << "\"/>\n"
    << "      <inertia ixx=\"1e-6\" ixy=\"0\" ixz=\"0\" iyy=\"1e-6\" iyz=\"0\" izz=\"1e-12\"/>"
    << "</inertial>\n    <collision><geometry><cylinder radius=\"" << radius << "\" length=\""
    << length << "\"/></geometry></collision>\n  </link>\n"
    << "  <evsim_device max_insertion_speed=\"0.05\" max_rotation_speed=\"6.28\"/>\n"
    << "  <evsim_section link=\"shaft\" young_modulus=\"" << young_modulus
    << "\" poisson_ratio=\"0.33\" elements=\"" << elements << "\"/>\n</robot>\n";
  return s.str();
}

}  // namespace test
}  // namespace evsim
