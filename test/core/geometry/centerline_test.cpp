// SWC centreline files: valid ones load; malformed ones name the file and line.
#include "endovascular_sim/geometry/centerline.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

const char* kValid =
    "# a small tree\n"
    "# units: mm\n"
    "1 1 0 0 0 3.5 -1\n"
    "2 1 0 0 10 3.4 1\n"
    "3 2 2 0 20 2.5 2\n"
    "4 3 -2 0 20 2.0 2\n";

std::string writeSwc(const std::string& text) {
  const fs::path p =
      fs::temp_directory_path() /
      ("evsim_swc_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
       ".swc");
  std::ofstream(p) << text;
  return p.string();
}

LoadError errorFor(const std::string& text) {
  const std::string path = writeSwc(text);
  try {
    loadCenterlineFile(path);
  } catch (const LoadError& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return LoadError("", 0, "", "");
}

void expectAt(const LoadError& e, int line, const std::string& field, const std::string& words) {
  EXPECT_NE(e.file().find("evsim_swc_"), std::string::npos) << e.what();
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.field(), field) << e.what();
  EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
}

TEST(Centerline, ValidFileLoadsInMetres) {
  const Centerline c = loadCenterlineFile(writeSwc(kValid));
  ASSERT_EQ(c.numPoints(), 4);
  EXPECT_EQ(c.numSegments(), 3);
  EXPECT_DOUBLE_EQ(c.radius[0], 3.5e-3);
  EXPECT_EQ(c.parent[3], 1);
  EXPECT_NEAR(c.position[2].z(), 0.02, 1e-15);
}

TEST(Centerline, Cycle) {
  expectAt(errorFor("1 1 0 0 0 1 3\n2 1 0 0 1 1 1\n3 1 0 0 2 1 2\n"), 1, "parent", "cycle");
}

TEST(Centerline, NegativeRadius) {
  expectAt(errorFor("# x\n1 1 0 0 0 1 -1\n2 1 0 0 1 -0.5 1\n"), 3, "radius", "must be positive");
}

TEST(Centerline, ZeroRadius) {
  expectAt(errorFor("1 1 0 0 0 0 -1\n"), 1, "radius", "must be positive");
}

TEST(Centerline, ARadiusOrCoordinateOfAnotherScaleIsRefused) {
  // In mm (the default): 1e308 mm would make a field of kernels that takes
  // minutes to build (found by the fuzz test).
  expectAt(errorFor("1 1 0 0 0 1 -1\n2 1 0 0 1 1e308 1\n"), 2, "radius",
           "beyond the largest vessel radius");
  expectAt(errorFor("1 1 0 0 0 1 -1\n2 1 2e4 0 1 1 1\n"), 2, "x", "beyond 10 m");
}

TEST(Centerline, NaN) {
  expectAt(errorFor("1 1 0 0 0 1 -1\n2 1 0 nan 1 1 1\n"), 2, "y", "must be finite");
}

TEST(Centerline, DanglingParent) {
  expectAt(errorFor("1 1 0 0 0 1 -1\n2 1 0 0 1 1 7\n"), 2, "parent", "no point with id 7");
}

TEST(Centerline, Empty) {
  const LoadError e = errorFor("# nothing here\n\n");
  EXPECT_NE(std::string(e.what()).find("no points"), std::string::npos) << e.what();
}

TEST(Centerline, WrongColumnCountAndDuplicateId) {
  expectAt(errorFor("1 1 0 0 0 1\n"), 1, "", "needs 7 columns");
  expectAt(errorFor("1 1 0 0 0 1 -1\n1 1 0 0 1 1 -1\n"), 2, "id", "appears twice");
  expectAt(errorFor("# units: furlong\n1 1 0 0 0 1 -1\n"), 1, "units", "unknown unit");
}

TEST(Centerline, SaveThenLoadRoundTrips) {
  const Centerline c = loadCenterlineFile(writeSwc(kValid));
  const std::string out = writeSwc("");
  saveCenterlineFile(c, out, "round trip");
  const Centerline d = loadCenterlineFile(out);
  ASSERT_EQ(d.numPoints(), c.numPoints());
  for (int i = 0; i < c.numPoints(); ++i) {
    EXPECT_LT((d.position[i] - c.position[i]).norm(), 1e-9);
    EXPECT_EQ(d.parent[i], c.parent[i]);
  }
}

}  // namespace
}  // namespace evsim
