// Messages as the node publishes them: every field of the core's contact,
// the friction force and the lumen flag included; device paths split at a
// detach.
#include "endovascular_sim/ros/message_conversions.h"

#include <gtest/gtest.h>

#include <memory>

#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/ros/scene_markers.h"

namespace evsim {
namespace {

TEST(ContactMessage, CarriesTheFrictionForceAndTheLumenFlag) {
  FrameSnapshot frame;
  frame.model = std::make_shared<const SceneModel>(loadScene("carotid_catheter"));
  Contact wall{0, 7, Vec3(0.01, 0.02, 0.03), Vec3::UnitZ()};
  wall.force = 0.5;
  wall.gap = -2e-7;
  wall.friction = Vec3(0.03, -0.04, 0.0);  // |f| = 0.05 N <= 0.2 * 0.5 N
  Contact lumen{1, 3, Vec3(0.0, 0.0, 0.1), Vec3::UnitY()};
  lumen.force = 0.2;
  lumen.other_device = 0;
  lumen.lumen = true;
  frame.contacts = {wall, lumen};

  const auto m = toContactArrayMsg(frame, std_msgs::Header());
  ASSERT_EQ(m.contacts.size(), 2u);
  EXPECT_EQ(m.contacts[0].device, "catheter");
  EXPECT_EQ(m.contacts[0].other_device, "");
  EXPECT_EQ(m.contacts[0].sample, 7u);
  EXPECT_DOUBLE_EQ(m.contacts[0].force, 0.5);
  EXPECT_DOUBLE_EQ(m.contacts[0].gap, -2e-7);
  EXPECT_DOUBLE_EQ(m.contacts[0].friction.x, 0.03);
  EXPECT_DOUBLE_EQ(m.contacts[0].friction.y, -0.04);
  EXPECT_DOUBLE_EQ(m.contacts[0].friction.z, 0.0);
  EXPECT_FALSE(m.contacts[0].lumen);
  EXPECT_EQ(m.contacts[1].device, "guidewire");
  EXPECT_EQ(m.contacts[1].other_device, "catheter");
  EXPECT_TRUE(m.contacts[1].lumen);
  EXPECT_DOUBLE_EQ(m.contacts[1].normal.y, 1.0);
}

TEST(DeviceStatusMessage, NamesTheVesselEachTipIsIn) {
  // The carotid scene's wire starts in the descending aorta: 120 mm
  // inserted up from z = -130 mm, its 180-degree J (10 mm of wire) curled
  // back, so the tip ends 20 mm below the arch's end at z = 0.
  FrameSnapshot frame;
  frame.model = std::make_shared<const SceneModel>(loadScene("carotid"));
  const SimData data = makeData(*frame.model);
  frame.devices = data.devices;
  frame.tips = data.tips;
  const auto m = toDeviceStatusMsg(frame, 0, std_msgs::Header());
  ASSERT_EQ(m.devices.size(), 1u);
  EXPECT_EQ(m.devices[0].tip_vessel, "descending_aorta");
  EXPECT_NEAR(m.devices[0].tip_depth, 0.020, 0.001);
  EXPECT_TRUE(m.devices[0].tip_in_lumen);
}

TEST(SceneMarkers, TargetsAreDrawnAlongTheirVesselAmberThenGreen) {
  FrameSnapshot frame;
  frame.model = std::make_shared<const SceneModel>(loadScene("arch_navigation"));
  const SimData data = makeData(*frame.model);
  frame.devices = data.devices;
  frame.targets = data.targets;
  auto targets = [&]() {
    std::vector<visualization_msgs::Marker> out;
    for (const auto& m : sceneMarkers(frame, MarkerStyle{}, {}).markers)
      if (m.ns == "targets") out.push_back(m);
    return out;
  };
  const auto before = targets();
  ASSERT_EQ(before.size(), frame.model->targets.size());
  // The first target's line runs from the left common carotid's origin on
  // the arch to its end (the SWC's last point of that vessel).
  const Centerline c = loadCenterlineFile(configDirectory() + "/vessels/carotid.swc");
  int last = -1;
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.vessel_names[c.vessel[i]] == "left_common_carotid") last = i;
  const auto& end = before[0].points.back();
  EXPECT_NEAR((Vec3(end.x, end.y, end.z) - c.position[last]).norm(), 0.0, 1e-9);
  EXPECT_GT(before[0].color.r, before[0].color.g);  // amber
  frame.targets[0].reached = true;
  EXPECT_GT(targets()[0].color.g, targets()[0].color.r);  // green
}

/// Triangles of the tube marker of device `i` (namespace "devices", id i).
size_t tubeTriangles(const visualization_msgs::MarkerArray& a, int i) {
  for (const auto& m : a.markers)
    if (m.ns == "devices" && m.id == i) return m.points.size() / 3;
  return 0;
}

TEST(SceneMarkers, ADetachedCoilsTubeIsOpenAtTheCut) {
  FrameSnapshot frame;
  frame.model = std::make_shared<const SceneModel>(loadScene("aneurysm_coiling"));
  frame.devices = makeData(*frame.model).devices;
  MarkerStyle style;
  const size_t nodes = frame.devices[1].position.size();
  const size_t per_element = 2 * static_cast<size_t>(style.tube_sides);
  EXPECT_EQ(tubeTriangles(sceneMarkers(frame, style, {}), 1), (nodes - 1) * per_element);
  frame.devices[1].cut_element = frame.model->devices[1].detach_element;
  EXPECT_EQ(tubeTriangles(sceneMarkers(frame, style, {}), 1), (nodes - 2) * per_element);
}

/// After a detach the pusher's path stops at the cut and the coil has its
/// own: neither runs across the cut element (nodes 2 -> 3 here).
TEST(PathMessage, ADetachedDeviceHasTwoPathsSplitAtTheCut) {
  DeviceState d;
  for (int i = 0; i < 5; ++i) {
    d.position.push_back(Vec3(0.001 * i, 0.0, 0.0));
    d.rotation.push_back(Quat::Identity());
  }
  const std_msgs::Header header;
  EXPECT_EQ(toPathMsg(d, header).poses.size(), 5u);
  EXPECT_TRUE(toDetachedPathMsg(d, header).poses.empty());
  d.cut_element = 2;
  const nav_msgs::Path pusher = toPathMsg(d, header), coil = toDetachedPathMsg(d, header);
  ASSERT_EQ(pusher.poses.size(), 3u);
  ASSERT_EQ(coil.poses.size(), 2u);
  EXPECT_DOUBLE_EQ(pusher.poses.back().pose.position.x, 0.002);
  EXPECT_DOUBLE_EQ(coil.poses.front().pose.position.x, 0.003);
  EXPECT_DOUBLE_EQ(coil.poses.back().pose.position.x, 0.004);
}

}  // namespace
}  // namespace evsim
