// Virtual fluoroscopy (imaging/): each projection is checked against a
// closed form computed here from the geometry alone: the line integral
// across a wire (mu pi r^2), the chord of a ray through a cylinder of
// contrast (2 sqrt(R^2 - p^2)), the pinhole projection of the AP view
// written out by hand, and the attenuation coefficients against NIST's
// published table (Hubbell & Seltzer, NISTIR 5632).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numeric>

#include "endovascular_sim/imaging/attenuation.h"
#include "endovascular_sim/imaging/detector.h"
#include "endovascular_sim/imaging/xray_renderer.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "test_helpers.h"

namespace evsim {
namespace {

/// No body: the projection of what the test places alone.
XraySpec bare(int pixels, double detector_size, int supersampling) {
  XraySpec x;
  x.present = true;
  x.body_width = x.body_depth = 0.0;
  x.c_arm.pixels = pixels;
  x.c_arm.detector_size = detector_size;
  x.c_arm.isocenter_given = true;
  x.c_arm.isocenter = Vec3::Zero();
  x.supersampling = supersampling;
  return x;
}

/// A scene of one straight solid wire of `radius` [m] in `material`.
SceneModel wireScene(double radius, double length, int elements, const std::string& material) {
  DeviceSpec spec = straightDeviceSpec("wire", test::wireSection(5e10, radius), length, elements);
  spec.sections[0].xray_material = findXrayMaterial(material);
  SceneModel m;
  m.devices.push_back(buildDeviceModel(spec));
  return m;
}

/// The wire's nodes on a line from a to b.
DevicePose along(const Vec3& a, const Vec3& b, int nodes) {
  DevicePose pose;
  for (int i = 0; i < nodes; ++i) pose.nodes.push_back(a + (b - a) * i / (nodes - 1.0));
  return pose;
}

TEST(Xray, AttenuationCoefficientsMatchNistsTable) {
  // NIST X-ray mass attenuation coefficients, mu/rho [cm^2/g] at 60 keV and
  // 80 keV: water 0.2059 and 0.1837, iodine 7.583 and 3.510, lead 5.021
  // and 2.419 (Hubbell & Seltzer, tables 3 and 4).
  struct Row {
    int Z;
    double kev, nist;
  };
  for (const Row& r :
       {Row{53, 60, 7.583}, Row{53, 80, 3.510}, Row{82, 60, 5.021}, Row{82, 80, 2.419}})
    EXPECT_NEAR(elementMassAttenuation(r.Z, r.kev) * 10.0, r.nist, 0.01 * r.nist)
        << "Z " << r.Z << " at " << r.kev << " keV";
  const double water60 =
      0.1119 * elementMassAttenuation(1, 60) + 0.8881 * elementMassAttenuation(8, 60);
  EXPECT_NEAR(water60 * 10.0, 0.2059, 0.01 * 0.2059);
  // Soft tissue near water; iodine contrast far above blood.
  const AttenuationTable t = attenuationAt(60.0);
  EXPECT_NEAR(t.soft_tissue, 1030.0 * water60, 0.05 * t.soft_tissue);
  EXPECT_GT(150.0 * t.iodine_mass, 5.0 * t.blood);
}

TEST(Xray, AWireAcrossTheBeamAttenuatesAsItsCrossSection) {
  // A 1 mm nitinol wire through the isocentre along the patient's left (x),
  // across the AP beam (along y). Across the wire, the line integral of the
  // image is mu * pi r^2 (the integral of the chord 2 sqrt(r^2 - x^2)); on
  // its axis, mu * 2r.
  const double r = 0.5e-3;
  const SceneModel scene = wireScene(r, 0.02, 10, "nitinol");
  for (int s : {1, 2, 4}) {
    XrayRenderer renderer(scene, bare(300, 0.03, s));  // 0.1 mm pixels, 1.5x
    const XrayCamera& cam = renderer.camera();
    XrayFrame frame;
    renderer.render({along(Vec3(-0.01, 0, 0), Vec3(0.01, 0, 0), 11)}, 0.0, &frame);
    const double mu = renderer.coefficients().device_material[findXrayMaterial("nitinol")];
    const int u = cam.width / 2 + 17;  // a column away from the nodes
    if (s == 1) {
      // One ray per pixel: row 149's ray, at its distance p from the axis
      // and its slant to it, meets the wire along 2 sqrt(r^2 - p^2) / sine.
      const Vec3 d = cam.ray(u, 149);
      const Vec3 n = d.cross(Vec3::UnitX());
      const double p = std::abs(cam.source.dot(n)) / n.norm();
      EXPECT_NEAR(frame.attenuation[149 * cam.width + u],
                  mu * 2 * std::sqrt(r * r - p * p) / n.norm(),
                  1e-6 * frame.attenuation[149 * cam.width + u]);
      continue;
    }
    // A pixel's rays over its area (the detector integrates over it): the
    // column's sum times the pixel's pitch at the wire's depth.
    double integral = 0.0;
    for (int v = 0; v < cam.height; ++v) integral += frame.attenuation[v * cam.width + u];
    integral *= cam.isocenterPixel();
    EXPECT_NEAR(integral, mu * M_PI * r * r, 0.01 * mu * M_PI * r * r) << s << " rays/side";
  }
}

TEST(Xray, ContrastInAStraightVesselFollowsTheChordLength) {
  // A straight vessel of radius R along the superior axis (z) through the
  // isocentre, filled with contrast: the ray of each column meets it along
  // 2 sqrt(R^2 - p^2), p the ray's distance from the axis (computed here
  // from the source and the column's direction).
  Centerline cl;
  const double R = 3e-3;
  for (int i = 0; i <= 20; ++i) {
    cl.position.push_back(Vec3(0, 0, -0.1 + 0.01 * i));
    cl.radius.push_back(R);
    cl.parent.push_back(i - 1);
    cl.type.push_back(1);
  }
  nameVessels(&cl);
  SceneModel scene;
  scene.vessels = std::make_shared<VesselField>(cl, std::vector<AneurysmSpec>{},
                                                std::vector<MotionRegion>{}, VesselFieldOptions{});
  scene.centerline = std::make_shared<Centerline>(cl);
  XraySpec spec = bare(200, 0.02, 1);
  XrayRenderer renderer(scene, spec);
  EXPECT_EQ(renderer.injectContrast(Vec3(0, 0, -0.1), 0.0, 1.0), 20);  // all downstream
  XrayFrame frame;
  renderer.render(std::vector<DevicePose>{}, 0.5, &frame);
  const XrayCamera& cam = renderer.camera();
  const double mu = spec.iodine_concentration * renderer.coefficients().iodine_mass;
  const int v = cam.height / 2;
  int compared = 0;
  for (int u = 0; u < cam.width; ++u) {
    const Vec3 d = cam.ray(u, v);
    // Distance between the ray's line and the z axis.
    const Vec3 n = d.cross(Vec3::UnitZ());
    const double p = std::abs(cam.source.dot(n)) / n.norm();
    const double a = frame.contrast[v * cam.width + u];
    if (p > 0.97 * R) {
      if (p > R) {
        EXPECT_EQ(a, 0.0f) << "column " << u;
      }
      continue;
    }
    // The ray is not perpendicular to the axis: its chord grows by 1/sin.
    const double sine = d.cross(Vec3::UnitZ()).norm();
    EXPECT_NEAR(a, mu * 2 * std::sqrt(R * R - p * p) / sine, 1e-4 * mu * R) << "column " << u;
    ++compared;
  }
  EXPECT_GT(compared, 50);
  // Washed out after the injection and its washout.
  renderer.render(std::vector<DevicePose>{}, 1.0 + spec.contrast_washout + 0.01, &frame);
  EXPECT_EQ(std::accumulate(frame.contrast.begin(), frame.contrast.end(), 0.0), 0.0);
}

/// A straight vessel of radius R along z through the origin, 21 points
/// 10 mm apart, and a branch of radius R/2 from its middle along +y.
Centerline straightVesselWithBranch(double R) {
  Centerline cl;
  for (int i = 0; i <= 20; ++i) {
    cl.position.push_back(Vec3(0, 0, -0.1 + 0.01 * i));
    cl.radius.push_back(R);
    cl.parent.push_back(i - 1);
    cl.type.push_back(1);
  }
  for (int i = 1; i <= 5; ++i) {
    cl.position.push_back(Vec3(0, 0.006 * i, 0));
    cl.radius.push_back(0.5 * R);
    cl.parent.push_back(i == 1 ? 10 : static_cast<int>(cl.position.size()) - 2);
    cl.type.push_back(1);
  }
  nameVessels(&cl);
  return cl;
}

TEST(Xray, ContrastInAMovingVesselFollowsItsChordWhereTheMotionCarriesIt) {
  // The vessel of the test above, carried 8 mm sideways (x) by a motion
  // region far wider than the view (its falloff 1 - 4e-6 across it), seen
  // at the peak of the motion: each column's value is the chord 2 sqrt(R^2
  // - p^2) / sin of the ray about the moved axis (p computed here). The
  // lumen is traced where the motion carried it, and only the segments that
  // hold contrast: the same pieces as the whole tree's trace.
  const double R = 3e-3, A = 8e-3, f = 1.0;
  const Centerline cl = straightVesselWithBranch(R);
  MotionRegion region;
  region.radius = 100.0;
  region.amplitude = Vec3(A, 0, 0);
  region.frequency = f;
  SceneModel scene;
  scene.vessels = std::make_shared<VesselField>(
      cl, std::vector<AneurysmSpec>{}, std::vector<MotionRegion>{region}, VesselFieldOptions{});
  scene.centerline = std::make_shared<Centerline>(cl);
  XraySpec spec = bare(200, 0.05, 1);
  XrayRenderer renderer(scene, spec);
  EXPECT_EQ(renderer.injectContrast(Vec3(0, 0, 0.005), 0.0, 1.0), 10);  // the upper half
  const double t = 0.25 / f;                                            // sin = 1
  XrayFrame frame;
  renderer.render(std::vector<DevicePose>{}, t, &frame);
  const XrayCamera& cam = renderer.camera();
  const double mu = spec.iodine_concentration * renderer.coefficients().iodine_mass;
  const MotionSnapshot motion = scene.vessels->motionAt(t);
  const Vec3 axis_point = scene.vessels->displacement(Vec3(0, 0, 0.05), motion);
  EXPECT_NEAR(axis_point.x(), A, 1e-8);
  const int v = cam.height / 4;  // a row through the vessel's upper half
  int compared = 0;
  for (int u = 0; u < cam.width; ++u) {
    const Vec3 d = cam.ray(u, v);
    const Vec3 n = d.cross(Vec3::UnitZ());
    const double p = std::abs((cam.source - axis_point).dot(n)) / n.norm();
    const double a = frame.contrast[v * cam.width + u];
    if (p > 0.97 * R) {
      if (p > R) {
        EXPECT_EQ(a, 0.0f) << "column " << u;
      }
      continue;
    }
    EXPECT_NEAR(a, mu * 2 * std::sqrt(R * R - p * p) / n.norm(), 1e-4 * mu * R) << "column " << u;
    ++compared;
  }
  EXPECT_GT(compared, 20);

  // The filled segments' pieces against the whole tree's trace.
  std::vector<char> filled(cl.numPoints(), 0);
  std::vector<double> mu_filled(cl.numPoints(), 0.0);
  for (int k = 11; k <= 20; ++k) filled[k] = 1, mu_filled[k] = 1.0;
  VesselProjection whole, part;
  whole.build(*scene.vessels, cl, {}, cam, 1, motion);
  part.build(*scene.vessels, cl, {}, cam, 1, motion, 0.0, &filled);
  std::vector<float> from_whole(cam.width * cam.height, 0.0f), from_part = from_whole;
  whole.addAttenuation(mu_filled, &from_whole);
  part.addAttenuation(mu_filled, &from_part);
  double largest = 0.0, difference = 0.0;
  for (size_t q = 0; q < from_whole.size(); ++q) {
    largest = std::max<double>(largest, from_whole[q]);
    difference = std::max<double>(difference, std::abs(from_whole[q] - from_part[q]));
  }
  EXPECT_GT(largest, 1.5 * R);
  EXPECT_LE(difference, 1e-9);
  EXPECT_LT(part.fieldEvaluations(), whole.fieldEvaluations());
}

TEST(Xray, AKnownPointProjectsWhereTheCameraSays) {
  // A short wire along the ray through X images as a dot centred on X's
  // projection. The AP view written out: the source behind the patient
  // (-y), the image's right the patient's left (+x), its top the head (+z).
  XraySpec spec = bare(256, 0.3, 4);
  const SceneModel scene = wireScene(0.6e-3, 0.004, 4, "platinum");
  XrayRenderer renderer(scene, spec);
  const XrayCamera& cam = renderer.camera();
  const Vec3 X(0.021, 0.013, -0.034);
  const double sod = spec.c_arm.source_isocenter_distance;
  const double f = spec.c_arm.source_detector_distance / (0.3 / 256);
  const Vec3 q = X - Vec3(0, -sod, 0);
  const double u_expected = 127.5 + f * q.x() / q.y(), v_expected = 127.5 - f * q.z() / q.y();
  EXPECT_NEAR(cam.project(X).x(), u_expected, 1e-9);
  EXPECT_NEAR(cam.project(X).y(), v_expected, 1e-9);

  const Vec3 along_ray = (X - cam.source).normalized();
  XrayFrame frame;
  renderer.render({along(X - 0.002 * along_ray, X + 0.002 * along_ray, 5)}, 0.0, &frame);
  double sum = 0.0, su = 0.0, sv = 0.0;
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const double a = frame.attenuation[v * cam.width + u];
      sum += a, su += a * u, sv += a * v;
    }
  ASSERT_GT(sum, 0.0);
  EXPECT_NEAR(su / sum, u_expected, 0.1);
  EXPECT_NEAR(sv / sum, v_expected, 0.1);
}

TEST(Xray, TheSpineShowsItsBodiesAndNotItsDiscs) {
  // A column of radius 20 mm along z through the isocentre, 25 mm bodies,
  // 5 mm discs, 30 % bone: the ray through the middle of a body meets bone
  // along 0.3 x its chord 2R / sin(slant); through a disc, none.
  XraySpec spec = bare(256, 0.3, 1);
  spec.spine.present = true;
  spec.spine.center = Vec3::Zero();
  const SceneModel nothing;  // (the renderer keeps a reference)
  XrayRenderer renderer(nothing, spec);
  const XrayCamera& cam = renderer.camera();
  XrayFrame frame;
  renderer.render(std::vector<DevicePose>{}, 0.0, &frame);
  const AttenuationTable& mu = renderer.coefficients();
  const double excess = spec.spine.bone_fraction * (mu.bone - mu.soft_tissue);
  for (double s : {0.0125, 0.0125 - 0.03, 0.0125 + 0.06}) {  // middles of bodies
    const Vec3 p = cam.project(Vec3(0, 0, s));
    const int u = static_cast<int>(std::lround(p.x())), v = static_cast<int>(std::lround(p.y()));
    const Vec3 d = cam.ray(u, v);
    const Vec3 n = d.cross(Vec3::UnitZ());
    const double off = std::abs(cam.source.dot(n)) / n.norm();  // the ray's distance from the axis
    const double R = spec.spine.radius;
    EXPECT_NEAR(frame.attenuation[v * cam.width + u],
                excess * 2 * std::sqrt(R * R - off * off) / n.norm(), 1e-5)
        << "body at " << s;
  }
  for (double s : {0.0275, 0.0275 - 0.03}) {  // middles of discs
    const Vec3 p = cam.project(Vec3(0, 0, s));
    EXPECT_EQ(frame.attenuation[std::lround(p.y()) * cam.width + std::lround(p.x())], 0.0f)
        << "disc at " << s;
  }
}

TEST(Xray, LaoAndCranialTurnTheBeamAsCliniciansSayIt) {
  // LAO 90: the detector on the patient's left, the beam along +x; cranial
  // 30 from AP: the beam tilted up towards the head.
  CArmSpec c;
  c.lao = M_PI / 2;
  EXPECT_NEAR((cameraOf(c, Vec3::Zero()).beam() - Vec3::UnitX()).norm(), 0.0, 1e-12);
  c.lao = 0.0;
  c.cranial = M_PI / 6;
  EXPECT_NEAR((cameraOf(c, Vec3::Zero()).beam() - Vec3(0, std::cos(M_PI / 6), 0.5)).norm(), 0.0,
              1e-12);
  // Any pose: the isocentre projects to the detector's centre.
  c.lao = -0.4;
  c.cranial = -0.3;
  const XrayCamera cam = cameraOf(c, Vec3(0.01, 0.02, 0.03));
  EXPECT_NEAR(cam.project(Vec3(0.01, 0.02, 0.03)).x(), cam.cx, 1e-9);
  EXPECT_NEAR(cam.project(Vec3(0.01, 0.02, 0.03)).y(), cam.cy, 1e-9);
  c.source_isocenter_distance = 0.0;
  EXPECT_NE(validateCArm(c), "");
  c.source_isocenter_distance = 0.8;
  c.pixels = 0;
  EXPECT_NE(validateCArm(c), "");
}

TEST(Xray, ContrastFillsTheVesselsDownstreamOfTheTip) {
  // In the arch, contrast let out in the left common carotid fills it and
  // its internal and external carotids, and no other vessel.
  const SceneModel scene = loadScene("carotid");
  ContrastAgent agent(scene.centerline);
  const VesselAtlas& atlas = *scene.atlas;
  const int lcc = atlas.find("left_common_carotid");
  const Vec3 at = atlas.pointAt(lcc, 0.03);
  agent.inject(at, 0.0, 1.0, 100.0, 1.0);
  const Centerline& cl = *scene.centerline;
  for (int k = 0; k < cl.numPoints(); ++k) {
    if (cl.parent[k] < 0) continue;
    const std::string& name = cl.vessel_names[cl.vessel[k]];
    const bool downstream = name == "left_internal_carotid" || name == "left_external_carotid" ||
                            (name == "left_common_carotid" &&
                             atlas.locateIn(lcc, cl.position[k]).depth >= 0.03 - 0.006);
    if (name == "left_common_carotid" &&
        std::abs(atlas.locateIn(lcc, cl.position[k]).depth - 0.03) < 0.006)
      continue;  // the segment holding the point itself
    EXPECT_EQ(agent.concentration(k, 0.5) > 0.0, downstream) << name << " point " << k;
  }
}

TEST(Xray, NoiseIsSeededAndUnbiased) {
  XraySpec spec = bare(64, 0.05, 1);
  spec.photons = 1000.0;
  XrayFrame frame;
  frame.width = frame.height = 64;
  frame.attenuation.assign(64 * 64, 0.5f);
  const auto a = detectorGray(frame, spec, 0.0, 7), b = detectorGray(frame, spec, 0.0, 7),
             c = detectorGray(frame, spec, 0.0, 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  spec.photons = 0.0;
  const auto clean = detectorGray(frame, spec, 0.0, 7);
  EXPECT_EQ(clean[0],
            static_cast<std::uint8_t>(std::lround(kBackgroundGray - kGrayPerAttenuation * 0.5)));
  const double mean = std::accumulate(a.begin(), a.end(), 0.0) / a.size();
  // log of counts: the noise's standard deviation 100 / sqrt(1000 e^-0.5)
  // gray levels a pixel, its mean over 4096 pixels within 0.2.
  EXPECT_NEAR(mean, clean[0], 0.3);
}

}  // namespace
}  // namespace evsim
