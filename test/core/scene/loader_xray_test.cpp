// The X-ray inputs: a scene's `xray:` section and a device's radiopaque
// materials and marker bands; each bad value gives an error that names the
// file, the line and the field (the line known here by construction).
#include <gtest/gtest.h>

#include <cmath>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/scene/scene_file.h"
#include "loader_fixture.h"

namespace evsim {
namespace {

using test::expectNames;
using test::kDevice;
using test::kScene;
using test::Loader;

/// kScene's `script:` is its line 10: an `xray:` put before it is there.
constexpr int kXrayLine = 10;

TEST_F(Loader, AnXraySectionIsReadInClinicalUnits) {
  write("wire.urdf", kDevice);
  std::string text = kScene;
  text.replace(text.find("script:"), 7,
               "xray: {lao_deg: 30, cranial_deg: -15, pixels: 256, isocenter: [0, 0, 0.04]}\n"
               "script:");
  const SceneSpec s = loadSceneFile(write("scene.yaml", text));
  EXPECT_TRUE(s.xray.present);
  EXPECT_NEAR(s.xray.c_arm.lao, M_PI / 6, 1e-15);
  EXPECT_NEAR(s.xray.c_arm.cranial, -M_PI / 12, 1e-15);
  EXPECT_EQ(s.xray.c_arm.pixels, 256);
  EXPECT_TRUE(s.xray.c_arm.isocenter_given);
  EXPECT_EQ(s.xray.c_arm.isocenter, Vec3(0, 0, 0.04));
  // Without the section: absent, the documented defaults.
  EXPECT_FALSE(loadSceneFile(write("plain.yaml", kScene)).xray.present);
}

TEST_F(Loader, AnXrayPoseThatCannotImageIsRefusedWithItsKey) {
  struct Case {
    const char* section;
    const char* words;
  };
  for (const Case& c :
       {Case{"{pixels: 0}", "pixels"},
        Case{"{source_isocenter_distance: 0}", "source_isocenter_distance"},
        Case{"{source_detector_distance: 1.0, source_isocenter_distance: 1.2}",
             "source_isocenter_distance"},
        Case{"{lao_deg: 120}", "lao_deg"}, Case{"{cranial_deg: .nan}", "cranial_deg"},
        Case{"{detector_size: 0}", "detector_size"}, Case{"{frame_rate: 1000}", "frame_rate"},
        Case{"{left: [1, 0, 0], anterior: [1, 1, 0]}", "perpendicular"},
        Case{"5", "must be a map"}}) {
    const LoadError e = sceneError("script:", std::string("xray: ") + c.section + "\nscript:");
    EXPECT_EQ(e.line(), kXrayLine) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos)
        << c.section << ": " << e.what();
  }
  const LoadError typo = sceneError("script:", "xray: {lao: 30}\nscript:");
  EXPECT_NE(std::string(typo.what()).find("lao_deg"), std::string::npos) << typo.what();
}

TEST_F(Loader, RadiopaqueMaterialsAndMarkersReachTheDeviceModel) {
  std::string text = kDevice;
  text.replace(text.find("elements=\"30\""), 13, "elements=\"30\" xray_material=\"nitinol\"");
  text.replace(text.find("rest_curvature=\"0 0 100\""), 24,
               "rest_curvature=\"0 0 100\" xray_material=\"platinum\" xray_fill=\"0.5\"");
  text.replace(text.find("</robot>"), 8,
               "  <evsim_marker link=\"tip\" position=\"0.018\" length=\"0.001\" "
               "material=\"platinum_iridium\"/>\n</robot>");
  const DeviceModel m = buildDeviceModel(loadDeviceFile(write("wire.urdf", text)));
  EXPECT_EQ(m.section_xray_material[0], findXrayMaterial("nitinol"));
  EXPECT_EQ(m.section_xray_material[1], findXrayMaterial("platinum"));
  EXPECT_EQ(m.section_xray_fill[1], 0.5);
  ASSERT_EQ(m.xray_markers.size(), 1u);
  EXPECT_NEAR(m.xray_markers[0].s_begin, 0.3 + 0.018, 1e-15);  // after the 0.3 m shaft
  EXPECT_NEAR(m.xray_markers[0].s_end, 0.3 + 0.019, 1e-15);
  // No material named: the documented default.
  const DeviceModel plain = buildDeviceModel(loadDeviceFile(write("plain.urdf", kDevice)));
  EXPECT_EQ(plain.section_xray_material[0], findXrayMaterial(kDefaultXrayMaterial));
}

TEST_F(Loader, AnUnknownMaterialOrAMarkerBeyondItsLinkIsNamed) {
  // The shaft's <evsim_section> is line 15 of kDevice, the file's end line 18.
  expectNames(deviceError("elements=\"30\"", "elements=\"30\" xray_material=\"platnum\""),
              "wire.urdf", 15, "evsim_section[shaft]/xray_material", "did you mean 'platinum'");
  expectNames(deviceError("elements=\"30\"", "elements=\"30\" xray_fill=\"0\""), "wire.urdf", 15,
              "evsim_section[shaft]/xray_fill", "(0, 1]");
  expectNames(deviceError("</robot>",
                          "<evsim_marker link=\"tip\" position=\"0.0195\" length=\"0.001\" "
                          "material=\"platinum\"/></robot>"),
              "wire.urdf", 18, "evsim_marker/position", "beyond");
  expectNames(
      deviceError("</robot>",
                  "<evsim_marker link=\"nib\" length=\"0.001\" material=\"platinum\"/></robot>"),
      "wire.urdf", 18, "evsim_marker/link", "no section named 'nib'");
}

}  // namespace
}  // namespace evsim
