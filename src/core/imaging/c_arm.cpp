// The C-arm's projection as a pinhole camera: the X-ray source is the centre
// of projection, the detector the image plane. Declared and documented in
// endovascular_sim/imaging/c_arm.h.
#include "endovascular_sim/imaging/c_arm.h"

#include <cmath>

namespace evsim {

XrayCamera cameraOf(const CArmSpec& c, const Vec3& isocenter) {
  const Vec3 left = c.left.normalized();
  const Vec3 anterior = c.anterior.normalized();
  const Vec3 superior = left.cross(anterior);
  // LAO turns the detector about the superior axis towards the patient's
  // left; cranial then tilts it about the image's horizontal axis towards
  // the head.
  const Vec3 horizontal = anterior * std::cos(c.lao) + left * std::sin(c.lao);
  const Vec3 x = left * std::cos(c.lao) - anterior * std::sin(c.lao);
  const Vec3 z = horizontal * std::cos(c.cranial) + superior * std::sin(c.cranial);
  const Vec3 y = z.cross(x);

  XrayCamera cam;
  cam.width = cam.height = c.pixels;
  const double pitch = c.detector_size / c.pixels;
  cam.fx = cam.fy = c.source_detector_distance / pitch;
  cam.cx = cam.cy = 0.5 * (c.pixels - 1);
  cam.rotation.row(0) = x.transpose();
  cam.rotation.row(1) = y.transpose();
  cam.rotation.row(2) = z.transpose();
  cam.isocenter = c.isocenter_given ? c.isocenter : isocenter;
  cam.source = cam.isocenter - z * c.source_isocenter_distance;
  cam.source_isocenter_distance = c.source_isocenter_distance;
  return cam;
}

}  // namespace evsim
