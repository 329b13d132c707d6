// A saved state resumes the run it came from bit for bit, and a bad state
// file is refused naming its line and field, the data kept.
#include "endovascular_sim/sim/state_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("evsim_state_test_" + name)).string();
}

std::vector<std::string> readLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void writeLines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream out(path);
  for (const std::string& line : lines) out << line << "\n";
}

/// Steps `data` n times, each step solved.
void run(const SceneModel& model, SimData* data, int n) {
  for (int k = 0; k < n; ++k) ASSERT_EQ(step(model, data), StepStatus::kOk) << data->last_error;
}

/// The coil of `aneurysm` after 300 steps: self-contacts and wall contacts
/// with forces (the next step's warm start), a scripted drive under way.
TEST(StateFile, AResumedRunMatchesTheUninterruptedOneBitForBit) {
  const SceneModel model = loadScene("aneurysm");
  SimData data = makeData(model);
  run(model, &data, 300);
  ASSERT_GT(data.contacts.size(), 0u);
  const std::string path = tempPath("resume.txt");
  ASSERT_TRUE(saveState(model, data, path));

  SimData resumed = makeData(model);
  loadState(model, path, &resumed);
  EXPECT_EQ(resumed.step, data.step);
  EXPECT_EQ(resumed.time, data.time);
  run(model, &data, 60);
  run(model, &resumed, 60);
  ASSERT_EQ(resumed.devices.size(), data.devices.size());
  for (size_t d = 0; d < data.devices.size(); ++d)
    for (size_t i = 0; i < data.devices[d].position.size(); ++i) {
      EXPECT_EQ(resumed.devices[d].position[i], data.devices[d].position[i]) << "node " << i;
      EXPECT_EQ(resumed.devices[d].velocity[i], data.devices[d].velocity[i]) << "node " << i;
    }
  EXPECT_EQ(resumed.contacts.size(), data.contacts.size());
  EXPECT_EQ(resumed.devices[0].inserted_length, data.devices[0].inserted_length);
  std::filesystem::remove(path);
}

/// The lines of a state of `model` saved after 50 steps (the file removed).
std::vector<std::string> savedStateLines(const SceneModel& model) {
  SimData data = makeData(model);
  run(model, &data, 50);
  const std::string good = tempPath("good.txt");
  EXPECT_TRUE(saveState(model, data, good));
  std::vector<std::string> lines = readLines(good);
  std::filesystem::remove(good);
  return lines;
}

/// Each kind of damage is refused with the line and field, and the data
/// loaded into stays as it was.
TEST(StateFile, ABadFileIsRefusedNamingLineAndFieldAndTheDataIsKept) {
  const SceneModel model = loadScene("aneurysm");
  const std::vector<std::string> lines = savedStateLines(model);
  ASSERT_GT(lines.size(), 8u);
  ASSERT_EQ(lines[4].rfind("node ", 0), 0u);

  struct Damage {
    std::string what;
    std::vector<std::string> lines;
    int line;
    std::string field;
  };
  std::vector<Damage> damages;
  {
    std::vector<std::string> l = lines;
    l[4].replace(5, l[4].find(' ', 5) - 5, "nan");  // the first node's x
    damages.push_back({"a NaN position", l, 5, "position"});
  }
  {
    std::vector<std::string> l = lines;
    l[1] = "scene carotid";
    damages.push_back({"another scene", l, 2, "scene"});
  }
  {
    std::vector<std::string> l(lines.begin(), lines.begin() + 6);
    damages.push_back({"a file cut short", l, 7, "node"});
  }
  {
    std::vector<std::string> l = lines;
    l[0] = "evsim_state 7";
    damages.push_back({"a newer version", l, 1, "version"});
  }
  {
    std::vector<std::string> l = lines;
    l[4] += " 1.0";
    damages.push_back({"a field too many", l, 5, "node"});
  }
  {
    std::vector<std::string> l = lines;
    std::istringstream clock(l[2]);
    std::string word, time;
    clock >> word >> time;
    l[2].replace(l[2].find(time), time.size(), "-1");
    damages.push_back({"a negative clock", l, 3, "time"});
  }
  {
    std::vector<std::string> l = lines;  // "device NAME NODES INSERTED ..."
    std::istringstream device(l[3]);
    std::string word, name, nodes, inserted;
    device >> word >> name >> nodes >> inserted;
    l[3].replace(l[3].find(" " + inserted + " ") + 1, inserted.size(), "-0.01");
    damages.push_back({"a negative inserted length", l, 4, "inserted length"});
  }
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind("contacts ", 0) == 0) {
      std::vector<std::string> l = lines;
      l[i] = "contacts 100000000";  // would allocate gigabytes
      damages.push_back({"millions of contacts", l, static_cast<int>(i) + 1, "contacts"});
    }
  const std::string bad = tempPath("bad.txt");
  SimData target = makeData(model);
  const long step_before = target.step;
  const std::vector<Vec3> position_before = target.devices[0].position;
  for (const Damage& damage : damages) {
    writeLines(bad, damage.lines);
    try {
      loadState(model, bad, &target);
      ADD_FAILURE() << damage.what << " was accepted";
    } catch (const LoadError& e) {
      EXPECT_EQ(e.file(), bad) << damage.what;
      EXPECT_EQ(e.line(), damage.line) << damage.what << ": " << e.what();
      EXPECT_EQ(e.field(), damage.field) << damage.what << ": " << e.what();
    }
    EXPECT_EQ(target.step, step_before) << damage.what;
    EXPECT_EQ(target.devices[0].position, position_before) << damage.what;
  }
  EXPECT_THROW(loadState(model, tempPath("absent.txt"), &target), LoadError);
  std::filesystem::remove(bad);
}

/// Three wrong values in one file (a negative clock, a negative inserted
/// length, a NaN position): all three, in file order, the data kept.
TEST(StateFile, EveryWrongValueOfAFileIsReportedAtOnce) {
  const SceneModel model = loadScene("aneurysm");
  std::vector<std::string> l = savedStateLines(model);
  ASSERT_EQ(l[2].rfind("clock ", 0), 0u);
  ASSERT_EQ(l[3].rfind("device ", 0), 0u);
  ASSERT_EQ(l[4].rfind("node ", 0), 0u);
  std::vector<std::string> clock, device;  // the records' fields
  for (const int k : {2, 3}) {
    std::istringstream fields(l[k]);
    std::vector<std::string>& out = k == 2 ? clock : device;
    for (std::string f; fields >> f;) out.push_back(f);
  }
  clock[1] = "-1";      // time
  device[3] = "-0.01";  // inserted length
  l[2] = l[3] = "";
  for (const auto& f : clock) l[2] += (l[2].empty() ? "" : " ") + f;
  for (const auto& f : device) l[3] += (l[3].empty() ? "" : " ") + f;
  l[4].replace(5, l[4].find(' ', 5) - 5, "nan");  // the first node's x
  const std::string bad = tempPath("bad3.txt");
  writeLines(bad, l);
  SimData target = makeData(model);
  const std::vector<Vec3> position_before = target.devices[0].position;
  try {
    loadState(model, bad, &target);
    ADD_FAILURE() << "three wrong values were accepted";
  } catch (const LoadErrors& e) {
    ASSERT_EQ(e.all().size(), 3u) << e.what();
    EXPECT_EQ(e.all()[0].line(), 3);
    EXPECT_EQ(e.all()[0].field(), "time");
    EXPECT_EQ(e.all()[1].line(), 4);
    EXPECT_EQ(e.all()[1].field(), "inserted length");
    EXPECT_EQ(e.all()[2].line(), 5);
    EXPECT_EQ(e.all()[2].field(), "position");
    EXPECT_NE(std::string(e.what()).find("(and 2 more"), std::string::npos) << e.what();
  }
  EXPECT_EQ(target.devices[0].position, position_before);
  std::filesystem::remove(bad);
}

}  // namespace
}  // namespace evsim
