// Every JSON line evsim prints (run --json, navigate's summary) is valid
// JSON whatever its strings hold: read back by a JSON parser, a reason of
// several kilobytes with quotes, backslashes, control characters and
// invalid UTF-8 comes back whole (invalid bytes replaced).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "endovascular_sim/sim/step_json.h"

namespace evsim {
namespace {

std::string awkwardReason() {
  std::string reason;
  for (int i = 0; i < 400; ++i) reason += "retry \"" + std::to_string(i) + "\\\" \t\n\x01 ";
  return reason;  // about 6 kB
}

TEST(JsonLines, TheAutopilotSummaryKeepsAReasonOfKilobytes) {
  const SceneModel model = loadScene("arch_navigation");
  const SimData data = makeData(model);
  AutopilotReport report;
  report.reason = awkwardReason();
  report.time = 1.25;
  report.peak_wall_force = std::numeric_limits<double>::quiet_NaN();
  const int target = model.atlas->find("left_subclavian");
  const std::string line = autopilotJson(model, data, target, 1, report);
  EXPECT_GT(line.size(), 5000u);
  EXPECT_EQ(line.find('\n'), std::string::npos);  // one line
  const nlohmann::json parsed = nlohmann::json::parse(line);
  EXPECT_EQ(parsed["reason"].get<std::string>(), report.reason);
  EXPECT_EQ(parsed["target"], "left_subclavian");
  EXPECT_EQ(parsed["device"], model.devices[1].name);
  EXPECT_EQ(parsed["time_s"].get<double>(), 1.25);
  EXPECT_TRUE(parsed["peak_wall_force_N"].is_null());  // NaN is not a JSON number
}

TEST(JsonLines, StepLinesReadBackToTheSameDoubles) {
  const SceneModel model = loadScene("carotid");
  SimData data = makeData(model);
  for (int i = 0; i < 20; ++i) step(model, &data);
  const nlohmann::json parsed = nlohmann::json::parse(stepJson(model, data));
  EXPECT_EQ(parsed["step"], data.step);
  EXPECT_EQ(parsed["t"].get<double>(), data.time);
  const Vec3& tip = data.devices[0].position.back();
  for (int k = 0; k < 3; ++k) EXPECT_EQ(parsed["devices"][0]["tip"][k].get<double>(), tip[k]);
}

TEST(JsonLines, InvalidUtf8IsReplacedNotThrown) {
  nlohmann::ordered_json o;
  o["name"] = std::string("wire\xff\xfe");
  const nlohmann::json parsed = nlohmann::json::parse(jsonLine(o));
  EXPECT_EQ(parsed["name"].get<std::string>().substr(0, 4), "wire");
}

}  // namespace
}  // namespace evsim
