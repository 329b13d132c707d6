// The shipped catheters' shapes at rest are the curves their documentation
// states (config/devices/README.md): each is integrated here as planar arcs
// from the documented lengths and angles, independently of the device
// model's frames, and compared with the model built from the URDF file.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {
namespace {

/// A planar piece of a device: its length [m] and the angle [rad] it turns
/// (> 0 toward the local +y of its start, about +z).
struct Arc {
  double length;
  double turn;
};

/// The end point and heading of arcs laid one after the other from the
/// origin along +x, by the closed form of a circular arc.
Vec3 endOf(const std::vector<Arc>& arcs, double* heading) {
  Vec3 p = Vec3::Zero();
  double h = 0.0;
  for (const Arc& a : arcs) {
    if (std::abs(a.turn) < 1e-15) {
      p += a.length * Vec3(std::cos(h), std::sin(h), 0.0);
    } else {
      const double k = a.turn / a.length;
      p += Vec3(std::sin(h + a.turn) - std::sin(h), std::cos(h) - std::cos(h + a.turn), 0.0) / k;
    }
    h += a.turn;
  }
  *heading = h;
  return p;
}

void expectRestShape(const std::string& file, const std::vector<Arc>& documented) {
  const DeviceModel m = buildDeviceModel(loadDeviceFile(configDirectory() + "/devices/" + file));
  double heading = 0.0;
  const Vec3 tip = endOf(documented, &heading);
  // The rest shape starts at the origin along +x (device_model.h). Within
  // 10 um and 1e-4 rad: the files give curvatures to 4 digits.
  EXPECT_LT((m.rest_position.back() - tip).norm(), 1e-5)
      << file << ": " << m.rest_position.back().transpose() << " vs " << tip.transpose();
  const Vec3 direction(std::cos(heading), std::sin(heading), 0.0);
  EXPECT_LT((m.rest_rotation.back().col(0) - direction).norm(), 1e-4) << file;
  double length = 0.0;
  for (const Arc& a : documented) length += a.length;
  EXPECT_NEAR(m.length, length, 1e-6) << file;
}

TEST(ShippedDevices, TheAngledCatheterTurns45DegreesOverItsLast20Millimetres) {
  expectRestShape("catheter.urdf", {{0.38, 0.0}, {0.02, M_PI / 4.0}});
}

TEST(ShippedDevices, TheMicrowiresTipTurns90DegreesOverItsLast3Millimetres) {
  expectRestShape("microwire.urdf", {{0.547, 0.0}, {0.003, M_PI / 2.0}});
}

TEST(ShippedDevices, TheHeadhunterTurns120DegreesOverItsLast30Millimetres) {
  expectRestShape("headhunter_catheter.urdf", {{0.37, 0.0}, {0.03, 2.0 * M_PI / 3.0}});
}

TEST(ShippedDevices, TheSimmonsDoublesBackAndItsTipTurnsAwayFromTheShaft) {
  // Shaft, a 180-degree knee of radius 10 mm, a 35 mm reversed limb, and a
  // 5 mm tip turned 30 degrees back toward +y (away from the shaft).
  const double knee = M_PI * 0.010;
  expectRestShape(
      "simmons_catheter.urdf",
      {{0.4 - knee - 0.035 - 0.005, 0.0}, {knee, M_PI}, {0.035, 0.0}, {0.005, -M_PI / 6.0}});
  // The limb runs 20 mm (the knee's diameter) beside the shaft, pointing back.
  const DeviceModel m =
      buildDeviceModel(loadDeviceFile(configDirectory() + "/devices/simmons_catheter.urdf"));
  EXPECT_GT(m.rest_position.back().y(), 0.020);
  EXPECT_LT(m.rest_rotation.back().col(0).x(), -0.8);
}

}  // namespace
}  // namespace evsim
