// Coil detachment (a device with a detach_section): refused while the
// junction is inside the microcatheter; afterwards the withdrawn pusher
// separates from the coil, which is left free.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/mechanics/elasticity.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "test_helpers.h"

namespace evsim {
namespace {

/// Mean position of the nodes beyond element `cut` (the coil) [m].
Vec3 coilCentroid(const DeviceState& x, int cut) {
  Vec3 c = Vec3::Zero();
  const int n = static_cast<int>(x.position.size());
  for (int i = cut + 1; i < n; ++i) c += x.position[i];
  return c / (n - cut - 1);
}

TEST(Detach, RefusedInsideTheMicrocatheterThenThePusherLeavesTheCoil) {
  const SceneModel model = loadScene("aneurysm_coiling");
  SimData data = makeData(model);
  const int coil = findDevice(model, "finishing_coil");
  ASSERT_GE(coil, 0);
  const int cut = model.devices[coil].detach_element;
  ASSERT_EQ(cut, 24);  // the pusher's 25th element joins it to the coil

  // At 1.0 s the junction is still inside the microcatheter: refused, state kept.
  while (data.time < 1.0 - 1e-9) ASSERT_EQ(step(model, &data), StepStatus::kOk) << data.last_error;
  const std::string why = detachDevice(model, &data, "finishing_coil");
  EXPECT_NE(why.find("still in the microcatheter"), std::string::npos) << why;
  EXPECT_EQ(data.devices[coil].cut_element, -1);
  EXPECT_NE(detachDevice(model, &data, "microcatheter").find("no detach_section"),
            std::string::npos);

  // The script detaches at 1.65 s and withdraws the pusher by 5 mm from 1.7 s.
  Vec3 coil_at_detach = Vec3::Zero(), pusher_at_detach = Vec3::Zero();
  while (data.time < 2.3 - 1e-9) {
    ASSERT_EQ(step(model, &data), StepStatus::kOk)
        << "t = " << data.time << ": " << data.last_error;
    for (const std::string& notice : data.notices)  // (the scene's target may be reached)
      ASSERT_EQ(notice.rfind("target 'aneurysm 0' reached", 0), 0u) << notice;
    if (std::abs(data.time - 1.7) < 1e-9) {
      ASSERT_EQ(data.devices[coil].cut_element, cut);
      coil_at_detach = coilCentroid(data.devices[coil], cut);
      pusher_at_detach = data.devices[coil].position[cut];
    }
  }
  const DeviceState& x = data.devices[coil];
  const double pusher_back = (x.position[cut] - pusher_at_detach).norm();
  // Joined, the junction element would keep its length (2 mm of steel
  // wire: at the scene's few newtons it stretches by under 1 um); cut, the
  // pusher's tip leaves the coil's proximal end behind. How far depends on
  // the coil's loops: packed into the dome, the coil may spring back into
  // the microcatheter after the detach, its end following the pusher by up
  // to 4.5 mm, or fall deeper into the dome (measured with lumen_settle 0.03
  // to 0.2 and curvature_loops 1 or every loop: junction 2.4-6.0 mm), so the
  // bound is 100x the joined element's stretch, not a share of the withdrawal.
  const double junction_rest = model.devices[coil].elements[cut].length;
  const double junction = (x.position[cut + 1] - x.position[cut]).norm();
  EXPECT_NEAR(pusher_back, 0.005, 0.0005);    // the commanded withdrawal
  EXPECT_GT(junction, junction_rest + 1e-4);  // joined: junction_rest
  const double coil_moved = (coilCentroid(x, cut) - coil_at_detach).norm();
  // The cut element stores no energy: the device's energy is its two parts'.
  DeviceState joined = x;
  joined.cut_element = -1;
  EXPECT_LT(elasticEnergy(model.devices[coil], x), elasticEnergy(model.devices[coil], joined));
  std::printf(
      "[ metric   ] pusher withdrawn %.3f mm; junction %.3f mm (rest %.3f mm); coil centroid "
      "moved %.3f mm\n",
      pusher_back * 1e3, junction * 1e3, junction_rest * 1e3, coil_moved * 1e3);
}

TEST(Detach, ThePusherPushedBackPushesTheDetachedCoil) {
  // A straight 0.25 mm "coil" (20 mm, 10 elements) behind a straight pusher
  // (30 mm, 10 elements: the junction element 3 mm) in dead_end's straight
  // 5 mm tube, no gravity: detached with the junction out of the
  // introducer, the pusher withdrawn 3 mm, then advanced 8 mm at 10 mm/s.
  // Its tip meets the coil's end head-on once it has closed the junction's
  // 3 mm and the 3 mm withdrawn, less the two radii (0.25 mm), and from
  // there pushes it: at the end of the push the coil's end has moved 8 - 3
  // - (3 - 0.25) = 2.25 mm along the tube, the two ends 0.25 mm apart. As one
  // body the pusher's tip and the coil's end were exempt as neighbours along
  // the device, and the tip ran into the coil.
  SceneSpec spec = loadSceneFile(resolveScenePath("dead_end"));
  DeviceSpec device = straightDeviceSpec("pusher", test::wireSection(60e9, 0.125e-3), 0.03, 10);
  DeviceSectionSpec coil = device.sections[0];
  coil.name = "coil";
  coil.section = test::wireSection(2e9, 0.125e-3, 21450.0);
  coil.length = 0.02;
  device.sections.push_back(coil);
  device.detach_section = "coil";
  device.name = "coil";
  spec.devices[0].device = device;
  spec.devices[0].inserted_length = 0.026;  // the coil and the junction past the introducer
  spec.effects = {"device_contact"};
  spec.gravity = Vec3::Zero();
  spec.script.clear();
  const SceneModel model = buildSceneModel(spec);
  SimData data = makeData(model);
  const int cut = model.devices[0].detach_element;
  ASSERT_EQ(cut, 9);
  const double r_sum = 2 * 0.125e-3, junction = 0.003;
  auto run = [&](double speed, double until) {
    DriveCommand command;
    command.insertion = speed;
    ASSERT_EQ(setCommand(model, &data, "coil", command), "");
    while (data.time < until - 1e-9)
      ASSERT_EQ(step(model, &data), StepStatus::kOk)
          << "t = " << data.time << ": " << data.last_error;
  };
  run(0.0, 0.01);
  ASSERT_EQ(detachDevice(model, &data, "coil"), "");
  const Vec3 axis = spec.devices[0].introducer.frame.col(0);
  const Vec3 end_before = data.devices[0].position[cut + 1];
  run(-0.01, 0.31);  // 3 mm back
  run(0.01, 1.11);   // 8 mm forward
  const DeviceState& x = data.devices[0];
  const double moved = (x.position[cut + 1] - end_before).dot(axis);
  const double apart = (x.position[cut + 1] - x.position[cut]).norm();
  std::printf(
      "[ metric   ] pusher back 3 mm, then 8 mm on: the detached coil's end pushed %.4f mm "
      "(expected %.4f), the two ends %.4f mm apart (radii %.4f mm)\n",
      moved * 1e3, (0.008 - 0.003 - (junction - r_sum)) * 1e3, apart * 1e3, r_sum * 1e3);
  EXPECT_NEAR(moved, 0.008 - 0.003 - (junction - r_sum), 2e-5);
  EXPECT_NEAR(apart, r_sum, 1e-5);  // (the pushed coil runs a few um ahead between steps)
}

// The scene is a hard case: from 0.7 s the coil whips its loops round the
// dome (tip jumps of 1-8 mm in a step) and at 1.35-1.6 s the stiff pusher
// straightens the microcatheter's tip. With 20 loops and 4 halvings a 1 %
// change of the insertion speed (or of the round-off) left a step unsolved;
// the scene asks for 30 and 10. Pushed 2 % slower and faster, every step
// must still be solved.
TEST(Detach, CoilingSurvivesSmallChangesOfTheInsertionSpeed) {
  for (double factor : {0.98, 1.02}) {
    SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm_coiling"));
    ASSERT_GT(spec.script[0].command.insertion, 0.0);
    spec.script[0].command.insertion *= factor;
    const SceneModel model = buildSceneModel(spec);
    SimData data = makeData(model);
    int subdivided = 0;
    while (data.time < 1.7 - 1e-9) {
      ASSERT_EQ(step(model, &data), StepStatus::kOk)
          << "speed x" << factor << ", t = " << data.time << ": " << data.last_error;
      subdivided += data.stats.subdivisions > 0;
    }
    std::printf("[ metric   ] insertion speed x%.2f: 1,700 steps solved, %d subdivided\n", factor,
                subdivided);
  }
}

/// Distance [m] from p to the nearest segment of an SWC polyline, and that
/// segment's radius.
std::pair<double, double> nearestSegment(const Centerline& c, const Vec3& p) {
  std::pair<double, double> best{1e9, 0.0};
  for (int i = 0; i < c.numPoints(); ++i) {
    if (c.parent[i] < 0) continue;
    const Vec3 a = c.position[c.parent[i]], b = c.position[i];
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const double d = (p - a - t * (b - a)).norm();
    if (d < best.first) best = {d, c.radius[i]};
  }
  return best;
}

// The scene's target: the detached coil in the aneurysm's sac. Judged here
// from the SWC polyline and the dome's numbers in the scene file, not the
// atlas the target tracker uses: every coil node outside the parent
// artery's lumen, and the coil's centroid inside the dome.
TEST(Detach, TheDetachedCoilLiesInTheSacAndTheTargetSaysSo) {
  const SceneModel model = loadScene("aneurysm_coiling");
  ASSERT_EQ(model.targets.size(), 1u);
  ASSERT_EQ(model.targets[0].spec.aneurysm, 0);
  SimData data = makeData(model);
  while (data.time < model.duration - 1e-9)
    ASSERT_EQ(step(model, &data), StepStatus::kOk) << data.last_error;
  ASSERT_EQ(data.targets.size(), 1u);
  EXPECT_TRUE(data.targets[0].reached);
  EXPECT_GT(data.targets[0].reached_time, 1.65 + 0.5 - 1e-9);  // detached at 1.65 s, then 0.5 s
  const int coil = findDevice(model, "finishing_coil");
  const int cut = model.devices[coil].detach_element;
  const DeviceState& x = data.devices[coil];
  const Centerline ica = loadCenterlineFile(configDirectory() + "/vessels/aneurysm.swc");
  const SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm_coiling"));
  const AneurysmSpec dome = spec.vessels.aneurysms.at(0);
  double closest_to_ica = 1e9;
  for (int i = cut + 1; i < static_cast<int>(x.position.size()); ++i) {
    const auto [d, r] = nearestSegment(ica, x.position[i]);
    closest_to_ica = std::min(closest_to_ica, d - r);
  }
  EXPECT_GT(closest_to_ica, 0.0);  // no node in the parent artery's lumen
  EXPECT_LT((coilCentroid(x, cut) - dome.center).norm(), dome.radius);
  std::printf(
      "[ metric   ] target reached at %.3f s; coil's nearest node %.2f mm outside the ICA lumen; "
      "centroid %.2f mm from the dome's centre (radius %.2f mm)\n",
      data.targets[0].reached_time, closest_to_ica * 1e3,
      (coilCentroid(x, cut) - dome.center).norm() * 1e3, dome.radius * 1e3);
}

// An aneurysm target names an aneurysm the vessels have and the device of
// a coil (one that detaches); anything else is refused at load with the
// file, the line and what is wrong.
TEST(Detach, AnAneurysmTargetIsCheckedAtLoad) {
  std::ifstream in(resolveScenePath("aneurysm_coiling"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string scene = buffer.str();
  for (const char* dir : {"../vessels/", "../devices/"}) {
    const std::string to = configDirectory() + "/" + std::string(dir).substr(3);
    for (size_t at = scene.find(dir); at != std::string::npos; at = scene.find(dir, at))
      scene.replace(at, std::strlen(dir), to);
  }
  const std::string target = "{aneurysm: 0, device: finishing_coil}";
  ASSERT_NE(scene.find(target), std::string::npos);
  struct Case {
    const char* target;
    const char* words;
  } cases[] = {{"{aneurysm: 3, device: finishing_coil}", "an index in [0, 0]"},
               {"{aneurysm: 0}", "names the coil's device"},
               {"{aneurysm: 0, device: microcatheter}", "no section that detaches"},
               {"{aneurysm: 0, vessel: internal_carotid, device: finishing_coil}",
                "a vessel or an aneurysm"},
               {"{aneurysm: 0, depth: 0.01, device: finishing_coil}", "applies to a vessel"}};
  const std::string path = ::testing::TempDir() + "/coiling_target.yaml";
  for (const Case& k : cases) {
    std::string text = scene;
    text.replace(text.find(target), target.size(), k.target);
    std::ofstream(path) << text;
    try {
      loadScene(path);
      ADD_FAILURE() << "accepted " << k.target;
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(k.words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("targets[0]"), std::string::npos) << e.what();
      EXPECT_GT(e.line(), 0) << e.what();
    }
  }
}

TEST(Detach, ACoilThatCannotFitItsAneurysmIsRefusedWithItsPackingDensity) {
  // aneurysm_coiling's 1 cm coil in domes of shrinking radius: the packing
  // density named is the coil's volume, summed here over the beam elements
  // of its detached part, over the sphere's; more than half is refused.
  SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm_coiling"));
  const SceneModel model = buildSceneModel(spec);
  const int coil = findDevice(model, "finishing_coil");
  ASSERT_GE(coil, 0);
  const DeviceModel& d = model.devices[coil];
  double volume = 0.0;  // of the elements after the cut
  for (int e = d.detach_element + 1; e + 1 < d.num_nodes; ++e)
    volume += M_PI * std::pow(d.node_radius[e], 2) * d.elements[e].length;
  for (const double radius : {0.5e-3, 0.6e-3, 0.7e-3}) {
    spec.vessels.aneurysms[0].radius = radius;
    const double density = volume / (4.0 / 3.0 * M_PI * std::pow(radius, 3));
    try {
      buildSceneModel(spec);
      EXPECT_LE(density, 0.5) << "accepted at " << density;
    } catch (const LoadError& e) {
      EXPECT_GT(density, 0.5) << e.what();
      const std::string what = e.what();
      const size_t at = what.find("would fill ");
      ASSERT_NE(at, std::string::npos) << what;
      EXPECT_NEAR(std::stod(what.substr(at + 11)), 100.0 * density, 1.0) << what;
      EXPECT_NE(what.find("targets[0]"), std::string::npos) << what;
      std::printf("[ metric   ] dome radius %.1f mm: %s\n", radius * 1e3, what.c_str());
    }
  }
}

}  // namespace
}  // namespace evsim
