// Named vessels: the names SWC files declare, the names the network
// generator makes, and where a point lies among them. Depths are checked
// against path lengths summed from the SWC points in the test itself.
#include "endovascular_sim/geometry/vessel_atlas.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/network_generator.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/targets.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

Centerline carotid() { return loadCenterlineFile(configDirectory() + "/vessels/carotid.swc"); }

TEST(VesselAtlas, TheArchNamesItsVessels) {
  const VesselAtlas atlas(carotid());
  for (const char* name :
       {"ascending_aorta", "aortic_arch", "descending_aorta", "brachiocephalic_trunk",
        "right_common_carotid", "left_common_carotid", "right_subclavian", "left_subclavian",
        "right_internal_carotid", "right_external_carotid", "left_internal_carotid",
        "left_external_carotid"})
    EXPECT_GE(atlas.find(name), 0) << name;
  EXPECT_EQ(atlas.vessels().size(), 12u);
  const NamedVessel& rcca = atlas.vessels()[atlas.find("right_common_carotid")];
  EXPECT_EQ(atlas.vessels()[rcca.parent].name, "brachiocephalic_trunk");
  EXPECT_EQ(rcca.generation, 3);  // ascending -> arch -> trunk -> carotid
}

TEST(VesselAtlas, DepthIsThePathLengthFromTheOrigin) {
  // Independent: walk the SWC points of the right common carotid from its
  // junction, summing distances; the point half way along a segment must
  // be found in that vessel at that depth.
  const Centerline c = carotid();
  const VesselAtlas atlas(c);
  const int v = atlas.find("right_common_carotid");
  double s = 0.0;
  int checked = 0;
  for (int i = 0; i < c.numPoints(); ++i) {
    if (c.vessel[i] != v) continue;
    const int p = c.parent[i];
    const double length = (c.position[i] - c.position[p]).norm();
    const Vec3 mid = 0.5 * (c.position[i] + c.position[p]);
    const VesselLocation at = atlas.locate(mid);
    if (s > 0.01) {  // past the ostium (inside the trunk's lumen it is the trunk)
      EXPECT_EQ(at.vessel, v) << "point " << i;
      EXPECT_NEAR(at.depth, s + 0.5 * length, 1e-9) << "point " << i;
      EXPECT_NEAR(at.radial, 0.0, 1e-9);
      ++checked;
    }
    s += length;
  }
  EXPECT_GT(checked, 10);
  EXPECT_NEAR(atlas.vessels()[v].length, s, 1e-9);
}

TEST(VesselAtlas, AnOstiumBelongsToTheParentAndAPointOutsideToTheNearest) {
  const VesselAtlas atlas(carotid());
  const int arch = atlas.find("aortic_arch"), trunk = atlas.find("brachiocephalic_trunk");
  // The trunk's origin lies on the arch's centreline: in the arch.
  const Vec3 origin = atlas.pointAt(trunk, 0.0);
  EXPECT_EQ(atlas.locate(origin).vessel, arch);
  // 5 mm past the arch's wall along the trunk: in the trunk.
  const double arch_radius = 13.5e-3;
  const VesselLocation in_trunk = atlas.locate(atlas.pointAt(trunk, arch_radius + 0.005));
  EXPECT_EQ(in_trunk.vessel, trunk);
  EXPECT_TRUE(in_trunk.inside);
  // Far outside every lumen: the nearest vessel, marked outside.
  const VesselLocation out = atlas.locate(Vec3(0.0, 0.0, -0.3));
  EXPECT_FALSE(out.inside);
  EXPECT_GT(out.radial, 1.0);
}

TEST(VesselAtlas, PathFromTheFemoralAccessToEachBranch) {
  const VesselAtlas atlas(carotid());
  auto names = [&](const std::vector<int>& path) {
    std::string out;
    for (int v : path) out += (out.empty() ? "" : " ") + atlas.vessels()[v].name;
    return out;
  };
  const int from = atlas.find("descending_aorta");
  EXPECT_EQ(names(atlas.path(from, atlas.find("right_common_carotid"))),
            "descending_aorta aortic_arch brachiocephalic_trunk right_common_carotid");
  EXPECT_EQ(names(atlas.path(from, atlas.find("left_subclavian"))),
            "descending_aorta aortic_arch left_subclavian");
  EXPECT_EQ(names(atlas.path(from, from)), "descending_aorta");
}

TEST(VesselAtlas, TheNetworkNamesEveryGeneratedVesselAfterItsParent) {
  Centerline c = carotid();
  NetworkOptions options;
  options.vessels = 400;
  const int added = growNetwork(options, &c);
  const VesselAtlas atlas(c);
  EXPECT_EQ(static_cast<int>(atlas.vessels().size()), 12 + added);
  std::mt19937 rng(3);
  int checked = 0;
  for (size_t v = 12; v < atlas.vessels().size(); v += 1 + rng() % 7) {
    const NamedVessel& vessel = atlas.vessels()[v];
    const std::string& parent = atlas.vessels()[vessel.parent].name;
    EXPECT_EQ(vessel.name.substr(0, parent.size() + 1), parent + "_") << vessel.name;
    // Its middle lies in it (generated vessels are 8-16 radii long).
    EXPECT_EQ(atlas.locate(atlas.pointAt(static_cast<int>(v), 0.6 * vessel.length)).vessel,
              static_cast<int>(v))
        << vessel.name;
    ++checked;
  }
  EXPECT_GT(checked, 40);
}

std::string writeSwc(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("evsim_atlas_" + name + ".swc");
  std::ofstream(p) << text;
  return p.string();
}

TEST(VesselAtlas, NamesRoundTripAndUnnamedRootsGetOne) {
  const std::string path = writeSwc("named",
                                    "# units: mm\n# vessel: trunk 1\n# vessel: side_branch 3\n"
                                    "1 1 0 0 0 3 -1\n2 1 0 0 10 3 1\n3 1 5 0 15 2 2\n"
                                    "4 1 50 0 0 2 -1\n");
  const Centerline c = loadCenterlineFile(path);
  ASSERT_EQ(c.vessel_names.size(), 3u);
  EXPECT_EQ(c.vessel_names[c.vessel[1]], "trunk");
  EXPECT_EQ(c.vessel_names[c.vessel[2]], "side_branch");
  EXPECT_EQ(c.vessel_names[c.vessel[3]], "vessel_4");
  const std::string copy = (fs::temp_directory_path() / "evsim_atlas_copy.swc").string();
  saveCenterlineFile(c, copy, "copy");
  const Centerline back = loadCenterlineFile(copy);
  for (int i = 0; i < c.numPoints(); ++i)
    EXPECT_EQ(back.vessel_names[back.vessel[i]], c.vessel_names[c.vessel[i]]);
}

TEST(VesselAtlas, BadNamesAreRefusedWithTheirLine) {
  struct Case {
    const char* header;
    const char* words;
  } cases[] = {{"# vessel: Trunk 1\n", "not a vessel name"},
               {"# vessel: trunk 9\n", "no point with id 9"},
               {"# vessel: trunk 1\n# vessel: trunk 2\n", "named twice"},
               {"# vessel: trunk\n", "needs '# vessel: NAME ID'"},
               {"# vessel: a 1\n# vessel: b 1\n", "already starts"}};
  for (const Case& k : cases) {
    const std::string path = writeSwc(
        "bad", std::string("# units: mm\n") + k.header + "1 1 0 0 0 3 -1\n2 1 0 0 9 3 1\n");
    try {
      loadCenterlineFile(path);
      ADD_FAILURE() << "accepted: " << k.header;
    } catch (const LoadError& e) {
      EXPECT_EQ(e.field(), "vessel") << e.what();
      EXPECT_GE(e.line(), 2) << e.what();
      EXPECT_NE(std::string(e.what()).find(k.words), std::string::npos) << e.what();
    }
  }
}

TEST(Targets, ReachedAfterTheDwellAndABreakRestartsIt) {
  const VesselAtlas atlas(carotid());
  Target target{TargetSpec{}, atlas.find("left_common_carotid"), -1};
  target.spec.vessel = "left_common_carotid";
  std::vector<TargetProgress> progress;
  auto at = [&](double depth, bool inside) {
    VesselLocation l;
    l.vessel = target.vessel;
    l.depth = depth;
    l.inside = inside;
    return std::vector<VesselLocation>{l};
  };
  std::vector<DeviceModel> models(1);
  models[0].name = "wire";
  const std::vector<DeviceState> devices(1);  // (a vessel target judges the tips alone)
  auto update = [&](double depth, double time) {
    return updateTargets({target}, at(depth, true), models, devices, atlas, time, &progress);
  };
  double t = 0.0;
  for (; t < 0.3; t += 0.01) update(0.025, t);
  EXPECT_FALSE(progress[0].reached);
  update(0.015, t);  // too shallow: a break
  EXPECT_LT(progress[0].since, 0.0);
  const double back = t + 0.01;
  std::vector<std::string> notices;
  for (t = back; t < back + 0.6 && !progress[0].reached; t += 0.01) notices = update(0.03, t);
  ASSERT_TRUE(progress[0].reached);
  EXPECT_NEAR(progress[0].reached_time - back, 0.5, 0.011);
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("left_common_carotid"), std::string::npos);
  EXPECT_NEAR(progress[0].best_depth, 0.03, 1e-12);
}

// A vessel shorter than twice the target's depth holds no tip that deep (it
// is in a branch by then): half the vessel's length is enough there.
TEST(Targets, AShortVesselIsHeldAtHalfItsLength) {
  const VesselAtlas atlas(carotid());
  const int trunk = atlas.find("brachiocephalic_trunk");
  ASSERT_GE(trunk, 0);
  const double length = atlas.vessels()[trunk].length;  // 45 mm
  Target target{TargetSpec{}, trunk, -1};
  target.spec.vessel = "brachiocephalic_trunk";
  target.spec.depth = 0.1;  // [m] more than twice its length
  EXPECT_NEAR(requiredDepth(atlas.vessels()[trunk], 0.1), 0.5 * length, 1e-15);
  EXPECT_EQ(requiredDepth(atlas.vessels()[trunk], 0.02), 0.02);
  std::vector<DeviceModel> models(1);
  const std::vector<DeviceState> devices(1);
  auto heldFor = [&](double depth) {  // [s] until reached, within 2 s (-1: never)
    std::vector<TargetProgress> progress;
    VesselLocation tip;
    tip.vessel = trunk;
    tip.depth = depth;
    tip.inside = true;
    for (double t = 0.0; t < 2.0; t += 0.01) {
      updateTargets({target}, {tip}, models, devices, atlas, t, &progress);
      if (progress[0].reached) return t;
    }
    return -1.0;
  };
  EXPECT_LT(heldFor(0.5 * length - 0.001), 0.0);
  EXPECT_NEAR(heldFor(0.5 * length + 0.001), 0.5, 0.011);
}

}  // namespace
}  // namespace evsim
