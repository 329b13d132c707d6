// Generated arches (geometry/arch_generator.h, scene/arch_scene.h) against
// what was asked for, measured on the centreline itself: the arch type from
// the trunk's origin below the apex in left carotid diameters, the variants
// from which vessel each branch leaves, the draws' frequencies and radii
// against the statistics, no two lumens through each other, the surface
// against the radii, and the VMTK-style file read back as a patient's.
#include "endovascular_sim/geometry/arch_generator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "endovascular_sim/geometry/surface_fidelity.h"
#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "endovascular_sim/scene/arch_scene.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

/// Points of one named vessel, from its origin.
std::vector<int> pointsOf(const Centerline& c, const std::string& name) {
  std::vector<int> out;
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.vessel_names[c.vessel[i]] == name) out.push_back(i);
  return out;
}

/// The arch type measured: how far below the arch's apex (its highest
/// centreline point) the first branch leaves, in left carotid diameters.
int measuredType(const Centerline& c, const ArchParameters& p) {
  double apex = -1e9;
  for (int i = 0; i < c.numPoints(); ++i)
    if (c.vessel_names[c.vessel[i]].find("aort") != std::string::npos)
      apex = std::max(apex, c.position[i].z());
  const std::string first = p.aberrant_rsa ? "right_common_carotid" : "brachiocephalic_trunk";
  const int origin = c.parent[pointsOf(c, first).front()];
  const double lcca_diameter = 2.0 * c.radius[pointsOf(c, "left_common_carotid").front()];
  const double diameters = (apex - c.position[origin].z()) / lcca_diameter;
  return diameters < 1.0 ? 1 : diameters < 2.0 ? 2 : 3;
}

std::string parentVessel(const Centerline& c, const std::string& name) {
  const int origin = c.parent[pointsOf(c, name).front()];
  return c.vessel_names[c.vessel[origin]];
}

TEST(ArchGenerator, EachArchHasTheTypeAndVariantItWasDrawnWith) {
  for (int type = 1; type <= 3; ++type)
    for (int variant = 0; variant < 3; ++variant)
      for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        ArchDrawOptions o;
        o.type = type;
        o.bovine = variant == 1;
        o.aberrant_rsa = variant == 2;
        const ArchParameters p = drawArch(seed, o);
        SCOPED_TRACE(p.summary());
        const Centerline c = archCenterline(p);
        EXPECT_EQ(measuredType(c, p), type);
        EXPECT_EQ(parentVessel(c, "left_common_carotid"),
                  variant == 1 ? "brachiocephalic_trunk" : "aortic_arch");
        EXPECT_EQ(parentVessel(c, "right_subclavian"),
                  variant == 2 ? "aortic_arch" : "brachiocephalic_trunk");
        if (variant == 2) {  // the last branch of the arch, beyond the left subclavian
          EXPECT_GT(c.parent[pointsOf(c, "right_subclavian").front()],
                    c.parent[pointsOf(c, "left_subclavian").front()]);
        }
        EXPECT_EQ(parentVessel(c, "left_subclavian"), "aortic_arch");
        EXPECT_EQ(archTargets(p).size(), variant == 2 ? 4u : 5u);
      }
}

TEST(ArchGenerator, DrawsFollowThePopulationStatistics) {
  constexpr int kDraws = 2000;
  int types[4] = {0, 0, 0, 0}, bovine = 0;
  double lcca = 0.0, lcca2 = 0.0;
  for (int s = 0; s < kDraws; ++s) {
    const ArchParameters p = drawArch(1000 + s);
    ++types[static_cast<int>(p.type)];
    bovine += p.bovine;
    lcca += 2e3 * p.radius_lcca, lcca2 += std::pow(2e3 * p.radius_lcca, 2);
  }
  // Within 4 binomial standard errors of the frequencies asked for.
  auto near = [&](int count, double f) {
    EXPECT_NEAR(count / double(kDraws), f, 4.0 * std::sqrt(f * (1 - f) / kDraws)) << f;
  };
  // Wang et al. 2016 (n = 2370): type I 56.5 %, II 32.8 %, III 10.8 %;
  // bovine 13.6 % (Popieluszko et al. 2018), never with an aberrant
  // right subclavian (1.0 %, Terzioglu and Damar 2022).
  near(types[1], 0.565);
  near(types[2], 0.328);
  near(types[3], 0.107);
  near(bovine, 0.136 * (1 - 0.010));
  // The left carotid's diameter at its origin: 7.5 +- 1.4 mm
  // (Chassin-Trubert et al. 2020), drawn truncated at 2 SD: an SD of
  // 0.8796 of the untruncated one.
  const double mean = lcca / kDraws, sd = std::sqrt(lcca2 / kDraws - mean * mean);
  EXPECT_NEAR(mean, 7.5, 4.0 * 1.4 / std::sqrt(kDraws));
  EXPECT_NEAR(sd, 0.8796 * 1.4, 0.06);
}

TEST(ArchGenerator, NoTwoLumensPassThroughEachOther) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const ArchParameters p = drawArch(seed);
    const Centerline c = archCenterline(p);
    SCOPED_TRACE(p.summary());
    // Points of two vessels beyond their ostia (within the parent's radius,
    // their own and 2 mm of its origin a branch lies in its parent's lumen;
    // against its parent, twice that: the two lumens of a Y part there):
    // apart by more than their radii.
    auto beyondOstium = [&](const std::string& name, double reach) {
      const std::vector<int> all = pointsOf(c, name);
      const int origin = c.parent[all.front()];
      std::vector<int> out;
      for (int i : all)
        if (origin < 0 || (c.position[i] - c.position[origin]).norm() >
                              reach * (c.radius[origin] + c.radius[i] + 0.002))
          out.push_back(i);
      return out;
    };
    for (size_t a = 0; a < c.vessel_names.size(); ++a)
      for (size_t b = a + 1; b < c.vessel_names.size(); ++b) {
        const std::string& na = c.vessel_names[a];
        const std::string& nb = c.vessel_names[b];
        // (The aorta's three parts are one tube.)
        if (na.find("aort") != std::string::npos && nb.find("aort") != std::string::npos) continue;
        const bool related =
            (c.parent[pointsOf(c, na).front()] >= 0 && parentVessel(c, na) == nb) ||
            (c.parent[pointsOf(c, nb).front()] >= 0 && parentVessel(c, nb) == na);
        const std::vector<int> pa = beyondOstium(na, related ? 2.0 : 1.0),
                               pb = beyondOstium(nb, related ? 2.0 : 1.0);
        double closest = 1e9;
        for (int i : pa)
          for (int j : pb)
            closest = std::min(closest,
                               (c.position[i] - c.position[j]).norm() - c.radius[i] - c.radius[j]);
        EXPECT_GT(closest, 0.0) << na << " / " << nb;
      }
  }
}

TEST(ArchGenerator, TheSurfaceKeepsTheRadii) {
  const ArchParameters p = drawArch(7);
  const Centerline c = archCenterline(p);
  const SurfaceFidelity f = measureSurfaceFidelity(VesselField(c, {}, {}, {}), c);
  std::printf(
      "[ metric   ] generated arch: lumen radius against the centreline's, along the "
      "vessels median %.2f %% worst %.2f %% (%d rays); at forks median %.2f %%\n",
      100 * f.along.median, 100 * f.along.worst, f.along.rays, 100 * f.at_forks.median);
  EXPECT_GT(f.along.rays, 500);
  EXPECT_LT(f.along.median, 0.03);
  EXPECT_LT(f.along.worst, 0.15);
}

TEST(ArchGenerator, TheFilesLoadAsAPatientsDo) {
  const fs::path dir = fs::temp_directory_path() / "evsim_arch_generator_test";
  fs::remove_all(dir);
  ArchDrawOptions o;
  o.bovine = 0;
  o.aberrant_rsa = 0;
  const ArchParameters p = drawArch(3, o);
  const ArchScenes files = writeArchScenes(p, dir.string());
  const Centerline generated = archCenterline(p);
  const VesselAtlas truth(generated);
  ASSERT_EQ(files.target_scene.size(), 5u);
  for (const auto& [catheter, scene] : files.catheter_scene) {
    SCOPED_TRACE(scene);
    const SceneModel m = loadScene(scene);
    EXPECT_EQ(m.frame, "LAS");  // the file's field data
    EXPECT_NEAR(m.gravity.y(), -9.81, 1e-12);
    for (const char* name : {"brachiocephalic_trunk", "right_common_carotid", "right_subclavian",
                             "left_common_carotid", "left_subclavian", "aortic_arch",
                             "descending_aorta", "ascending_aorta"}) {
      SCOPED_TRACE(name);
      const int v = m.atlas->find(name);
      ASSERT_GE(v, 0);
      // The aorta split at its ostia and named as chains: the same vessels
      // as generated, within the simplification and the tree's welds.
      EXPECT_NEAR(m.atlas->vessels()[v].length, truth.vessels()[truth.find(name)].length, 2e-3);
    }
    SimData data = makeData(m);
    for (int k = 0; k < 10; ++k) ASSERT_EQ(step(m, &data), StepStatus::kOk) << data.last_error;
    EXPECT_EQ(m.atlas->vessels()[data.tips[1].vessel].name, "descending_aorta");
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace evsim
