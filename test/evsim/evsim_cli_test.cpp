// The evsim command line run as a user runs it: help, version, exit codes
// (0 done, 1 a step failed, 2 bad input), paths checked before a run, and
// the whole-scene bench's phases against the scene's own script.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace evsim {
namespace {

struct Outcome {
  int code{-1};
  std::string output;  // stdout and stderr
};

Outcome evsim(const std::string& arguments) {
  const std::string command = std::string(EVSIM_EVSIM_BINARY) + " " + arguments + " 2>&1";
  Outcome out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe)) out.output += buffer.data();
  const int status = pclose(pipe);
  out.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

bool says(const Outcome& o, const std::string& words) {
  return o.output.find(words) != std::string::npos;
}

/// A copy of shipped scene `name` at `file`, its vessel and device paths
/// made absolute, with `extra` appended (or, with `into_contact`, added to
/// the scene's contact map).
void writeSceneCopy(const std::string& name, const std::string& extra, const std::string& file,
                    bool into_contact = false) {
  namespace fs = std::filesystem;
  const std::string scenes = std::string(EVSIM_TEST_DATA_DIR) + "/../../config/scenes/";
  std::ifstream in(scenes + name + ".yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* what : {"../vessels/", "../devices/"}) {
    const std::string to = fs::canonical(fs::path(scenes) / what).string() + "/";
    for (size_t at; (at = text.find(what)) != std::string::npos;) text.replace(at, 11, to);
  }
  if (into_contact)
    text.insert(text.find("contact:\n") + 9, extra);
  else
    text += extra;
  std::ofstream(file) << text;
}

TEST(EvsimCli, HelpAndVersionExitZeroAndNameTheCommands) {
  const Outcome help = evsim("--help");
  EXPECT_EQ(help.code, 0);
  for (const char* command : {"run", "bench", "navigate", "mesh", "list"})
    EXPECT_TRUE(says(help, command));
  EXPECT_EQ(evsim("bench --help").code, 0);
  const Outcome version = evsim("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_TRUE(says(version, "evsim "));
}

TEST(EvsimCli, BadInputExitsTwoAndSaysWhy) {
  const Outcome unknown = evsim("frobnicate");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_TRUE(says(unknown, "unknown command 'frobnicate'"));
  const Outcome option = evsim("run free_insertion --nope");
  EXPECT_EQ(option.code, 2);
  EXPECT_TRUE(says(option, "--nope"));
  const Outcome number = evsim("run free_insertion --steps ten");
  EXPECT_EQ(number.code, 2);
  EXPECT_TRUE(says(number, "--steps"));
  const Outcome scene = evsim("run no_such_scene");
  EXPECT_EQ(scene.code, 2);
  EXPECT_TRUE(says(scene, "shipped: "));  // names the scenes that exist
  const Outcome spacing = evsim("mesh carotid --out /tmp/evsim_cli.ply --spacing 1e-7");
  EXPECT_EQ(spacing.code, 2);
  EXPECT_TRUE(says(spacing, "1e-4"));
}

TEST(EvsimCli, CheckPrintsEveryProblemOfASceneAtOnce) {
  const std::string bad = (std::filesystem::temp_directory_path() / "evsim_cli_bad.yaml").string();
  std::ofstream(bad) << "name: bad\ntime_step: 0.5\ngravty: [0, 0, -9.81]\n"
                        "devices: [{file: x.urdf, drive: {max_force: -2}}]\n";
  const std::string good = std::string(EVSIM_TEST_DATA_DIR) + "/../../config/scenes/carotid.yaml";
  const Outcome check = evsim("check " + bad + " " + good);
  EXPECT_EQ(check.code, 2);
  for (const std::string& line :
       {bad + ":2:12: time_step: must lie in [1e-6, 0.04] s, got 0.5",
        bad + ":3:1: gravty: unknown key 'gravty' (did you mean 'gravity'?)",
        bad + ":4:45: devices[0].drive.max_force: must be above 0 N, got -2", good + ": ok",
        std::string("1 valid, 1 with errors")})
    EXPECT_TRUE(says(check, line)) << line << "\n" << check.output;
  const Outcome run = evsim("run " + bad);
  EXPECT_EQ(run.code, 2);
  EXPECT_TRUE(says(run, "(and 2 more: `evsim check " + bad + "` lists every one)")) << run.output;
  // A device with two bad sections, an SWC file with two bad lines: both
  // problems of each.
  const std::string config = std::string(EVSIM_TEST_DATA_DIR) + "/../../config/";
  std::ifstream urdf_in(config + "devices/guidewire.urdf");
  std::string urdf((std::istreambuf_iterator<char>(urdf_in)), std::istreambuf_iterator<char>());
  for (const char* section :
       {"link=\"shaft\" young_modulus=\"6e10\"", "link=\"j_tip\" young_modulus=\"2e10\""}) {
    const size_t at = urdf.find(section);
    ASSERT_NE(at, std::string::npos);
    urdf.replace(urdf.find("young_modulus=", at) + 15, 4, "-1e9");
  }
  const std::string device =
      (std::filesystem::temp_directory_path() / "evsim_cli_bad.urdf").string();
  std::ofstream(device) << urdf;
  const std::string swc = (std::filesystem::temp_directory_path() / "evsim_cli_bad.swc").string();
  std::ofstream(swc) << "# units: mm\n1 1 0 0 0 3 -1\n2 1 0 0 x 3 1\n3 1 0 0 20 -3 2\n";
  const Outcome files = evsim("check " + device + " " + swc);
  EXPECT_EQ(files.code, 2);
  for (const std::string& words :
       {std::string("evsim_section[shaft]/young_modulus"),
        std::string("evsim_section[j_tip]/young_modulus"), swc + ":3: z: 'x' is not a number",
        swc + ":4: radius: must be positive"})
    EXPECT_TRUE(says(files, words)) << words << "\n" << files.output;
  const Outcome schema = evsim("schema");
  EXPECT_EQ(schema.code, 0);
  EXPECT_TRUE(says(schema, "| `time_step` | number | s | required | [1e-6, 0.04] |"));
}

TEST(EvsimCli, ABareCentrelineIsLookedAtAndRunWithItsUnits) {
  const std::string vtp =
      std::string(EVSIM_TEST_DATA_DIR) + "/../../config/vessels/example_patient.vtp";
  const Outcome vessels = evsim("vessels " + vtp + " --units mm");
  EXPECT_EQ(vessels.code, 0) << vessels.output;
  EXPECT_TRUE(says(vessels, "tree of 13 branches")) << vessels.output;
  const Outcome no_units = evsim("run " + vtp + " --steps 10");
  EXPECT_EQ(no_units.code, 2);
  EXPECT_TRUE(says(no_units, "units declared")) << no_units.output;
  const Outcome no_frame = evsim("run " + vtp + " --units mm --steps 10");
  EXPECT_EQ(no_frame.code, 2);  // the base lies supine: where is posterior?
  EXPECT_TRUE(says(no_frame, "vessels.frame")) << no_frame.output;
  const Outcome run = evsim("run " + vtp + " --units mm --frame LAS --steps 200");
  EXPECT_EQ(run.code, 0) << run.output;
  EXPECT_TRUE(says(run, "guidewire in branch_0")) << run.output;
}

TEST(EvsimCli, AnUnwritableOutputIsRefusedBeforeTheRun) {
  const Outcome save = evsim("run carotid --save-state /no/such/folder/state.txt");
  EXPECT_EQ(save.code, 2);
  EXPECT_TRUE(says(save, "cannot write /no/such/folder/state.txt"));
  EXPECT_FALSE(says(save, "t="));  // nothing was stepped
  const Outcome dump = evsim("run carotid --steps 5 --dump-lcp /proc/evsim_lcps");
  EXPECT_EQ(dump.code, 2);
  EXPECT_TRUE(says(dump, "--dump-lcp"));
}

TEST(EvsimCli, RunStepsTheScenesDurationByDefault) {
  // free_insertion's script ends at 4 s, its duration is 5 s: the last
  // progress line is at t = 5.
  const Outcome run = evsim("run free_insertion");
  EXPECT_EQ(run.code, 0);
  EXPECT_TRUE(says(run, "t=5 s"));
}

TEST(EvsimCli, BenchSortsTheStepsIntoPhases) {
  // free_insertion never touches anything: every step is 'free'; the
  // whole procedure is 5 s of 1 ms steps.
  const Outcome bench = evsim("bench free_insertion");
  EXPECT_EQ(bench.code, 0);
  EXPECT_TRUE(says(bench, "5000 steps of 1 ms"));
  EXPECT_TRUE(says(bench, "  free         5000"));
  EXPECT_TRUE(says(bench, "  whole        5000"));
  // carotid_selective: the J-tip touches the trunk's wall while it is pushed.
  const Outcome selective = evsim("bench carotid_selective --steps 800");
  EXPECT_EQ(selective.code, 0);
  EXPECT_TRUE(says(selective, "  contact "));
}

TEST(EvsimCli, BenchCopiesOfASmoothPathEndApartByTheirSpeedsDifference) {
  // carotid_selective's wire is pushed at 30 mm/s: over 0.8 s a copy whose
  // speed is k 1e-9 larger inserts k 2.4e-11 m more, and on a path that is
  // not chaotic its tip ends about that far from the scene's (it follows
  // the insertion along the trunk: within 40 %).
  const Outcome bench = evsim("bench carotid_selective --steps 800 --copies 2");
  ASSERT_EQ(bench.code, 0) << bench.output;
  for (int k = 1; k <= 2; ++k) {
    const std::string label = "copy " + std::to_string(k) + ": ";
    const size_t at = bench.output.find(label);
    ASSERT_NE(at, std::string::npos) << bench.output;
    const size_t tips = bench.output.find("tips ", at);
    ASSERT_NE(tips, std::string::npos);
    const double apart_mm = std::stod(bench.output.substr(tips + 5));
    const double expected_mm = k * 1e-9 * 0.03 * 0.8 * 1e3;
    EXPECT_GT(apart_mm, 0.6 * expected_mm) << label;
    EXPECT_LT(apart_mm, 1.4 * expected_mm) << label;
  }
  const size_t range = bench.output.find("the scene and its 2 copies: median ");
  ASSERT_NE(range, std::string::npos) << bench.output;
  double low = 0.0, high = 0.0;
  ASSERT_EQ(std::sscanf(bench.output.c_str() + range, "the scene and its 2 copies: median %lf-%lf",
                        &low, &high),
            2);
  EXPECT_LE(low, high);
  const Outcome many = evsim("bench carotid_selective --steps 10 --copies 21");
  EXPECT_EQ(many.code, 2);  // out of range: refused with a message
  EXPECT_TRUE(says(many, "--copies")) << many.output;
}

/// The numbers of a --windows line labelled `label`: loops after the first,
/// late wall, pair and lumen rows, mean rows, halved steps.
std::vector<double> windowLine(const Outcome& o, const std::string& label) {
  const size_t at = o.output.find("  " + label + " ");
  if (at == std::string::npos) return {};
  std::vector<double> v(6);
  if (std::sscanf(o.output.c_str() + at + 2 + label.size(), "%lf %lf %lf %lf %lf %lf", &v[0], &v[1],
                  &v[2], &v[3], &v[4], &v[5]) != 6)
    return {};
  return v;
}

TEST(EvsimCli, BenchWindowsRepeatTheRunAndAVariantEqualToTheSceneCountsTheSameWork) {
  // aneurysm's coil at t = 3.0-3.4 s, its turns meeting (late pair rows):
  // four windows of 25 steps. From the run's own states the scene's windows
  // repeat its steps (the state file is exact), and a variant that is the
  // same scene under another file counts exactly the same loops, rows and
  // halvings; one with 20x the penetration tolerance no more loops.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "evsim_cli_windows";
  fs::create_directories(dir);
  const std::string same = (dir / "same.yaml").string();
  const std::string loose = (dir / "loose.yaml").string();
  writeSceneCopy("aneurysm", "", same);
  writeSceneCopy("aneurysm", "  penetration_tolerance: 2.0e-5\n", loose, true);
  const Outcome bench =
      evsim("bench aneurysm --warmup 3000 --steps 400 --windows 4 " +
            std::string("--window-steps 25 --variant ") + same + " --variant " + loose);
  ASSERT_EQ(bench.code, 0) << bench.output;
  EXPECT_TRUE(says(bench, "the scene's windows repeat the run's loops step for step: yes"))
      << bench.output;
  const std::vector<double> scene = windowLine(bench, "aneurysm (the scene)");
  ASSERT_EQ(scene.size(), 6u) << bench.output;
  EXPECT_GT(scene[0], 0.0) << bench.output;  // loops after the first: the windows hold work
  EXPECT_EQ(windowLine(bench, "same.yaml"), scene) << bench.output;  // (by file name)
  const std::vector<double> relaxed = windowLine(bench, "loose.yaml");
  ASSERT_EQ(relaxed.size(), 6u) << bench.output;
  EXPECT_LE(relaxed[0], scene[0]) << bench.output;
  // A variant whose devices differ, or --variant alone: refused, nothing run.
  const Outcome other = evsim("bench carotid_selective --steps 50 --windows 2 --variant aneurysm");
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_TRUE(says(other, "--variant aneurysm: its devices differ")) << other.output;
  const Outcome alone = evsim("bench carotid_selective --steps 50 --variant " + same);
  EXPECT_EQ(alone.code, 2) << alone.output;
  EXPECT_TRUE(says(alone, "--variant needs --windows")) << alone.output;
  fs::remove_all(dir);
}

TEST(EvsimCli, AStepTheScenesOptionsCannotSolveIsRecoveredOrFailsWithStrict) {
  // carotid_selective with one PGS sweep: its first contact (t = 0.41 s)
  // is not solved by the scene's options; the recovery step solves it.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "evsim_cli_recovery";
  fs::create_directories(dir);
  const std::string scene = (dir / "pgs_one_sweep.yaml").string();
  writeSceneCopy("carotid_selective", "contact:\n  solver: pgs\n  max_iterations: 1\n", scene);
  const Outcome strict = evsim("run " + scene + " --steps 600 --strict");
  EXPECT_EQ(strict.code, 1) << strict.output;
  EXPECT_TRUE(says(strict, "iteration limit")) << strict.output;
  const Outcome recovered = evsim("run " + scene + " --steps 600");
  EXPECT_EQ(recovered.code, 0) << recovered.output;
  EXPECT_TRUE(says(recovered, "solved with the recovery options")) << recovered.output;
  EXPECT_TRUE(says(strict, "use the status method")) << strict.output;
  // Its advice names what is not set already: with the status method it
  // does not advise the status method.
  const std::string status = (dir / "status_one_pivot.yaml").string();
  writeSceneCopy("carotid_selective", "contact:\n  solver: status\n  max_iterations: 1\n", status);
  const Outcome pivot = evsim("run " + status + " --steps 600 --strict");
  EXPECT_EQ(pivot.code, 1) << pivot.output;
  EXPECT_TRUE(says(pivot, "raise contact.max_iterations (now 1)")) << pivot.output;
  EXPECT_FALSE(says(pivot, "use the status method")) << pivot.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

TEST(EvsimCli, NavigateRefusesAnUnknownTargetAndReportsAReachedOne) {
  const Outcome typo = evsim("navigate arch_navigation --target left_subclavain");
  EXPECT_EQ(typo.code, 2);
  EXPECT_TRUE(says(typo, "nearest: left_subclavian")) << typo.output;
  const Outcome missing = evsim("navigate carotid_selective");  // no --target, no targets
  EXPECT_EQ(missing.code, 2);
  EXPECT_TRUE(says(missing, "--target")) << missing.output;
  // Out of time before the arch: "not reached", with the reason, exit 1.
  // With every step written: one JSON line per step, as evsim run --json.
  const std::string steps = ::testing::TempDir() + "/navigate_steps.json";
  const Outcome early = evsim("navigate arch_navigation --target left_subclavian --timeout 0.2 " +
                              std::string("--steps-json ") + steps);
  EXPECT_EQ(early.code, 1) << early.output;
  EXPECT_TRUE(says(early, "\"reached\":false")) << early.output;
  EXPECT_TRUE(says(early, "\"reason\":\"out of time\"")) << early.output;
  std::ifstream lines(steps);
  std::string line, last;
  int count = 0;
  while (std::getline(lines, line)) {
    EXPECT_EQ(line.rfind("{\"step\":" + std::to_string(count + 1) + ",", 0), 0u) << line;
    ++count;
    last = line;
  }
  EXPECT_GE(count, 200);  // the timeout's steps (and the one that ends the run)
  EXPECT_LE(count, 202);
  EXPECT_NE(last.find("\"tip_vessel\""), std::string::npos) << last;
  const Outcome unwritable =
      evsim("navigate arch_navigation --target left_subclavian --steps-json /proc/nowhere/x.json");
  EXPECT_EQ(unwritable.code, 2) << unwritable.output;
  EXPECT_TRUE(says(unwritable, "--steps-json")) << unwritable.output;
  // Without --target: the scene's own (a procedure scene's one target).
  const Outcome reached = evsim("navigate arch_to_left_subclavian --quiet");
  EXPECT_EQ(reached.code, 0) << reached.output;
  EXPECT_TRUE(says(reached, "\"reached\":true")) << reached.output;
  EXPECT_TRUE(says(reached, "\"failed_steps\":0")) << reached.output;
  EXPECT_TRUE(says(reached, "\"final_vessel\":\"left_subclavian\"")) << reached.output;
}

/// The rows of a CSV file (the header first).
std::vector<std::vector<std::string>> csvRows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"')
        quoted = !quoted;
      else if (ch == ',' && !quoted)
        cells.push_back(cell), cell.clear();
      else
        cell += ch;
    }
    cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(EvsimCli, NavigationBenchDrawsItsNetworkTargetsFromTheSeed) {
  auto draw = [](int seed) {
    const std::string csv = "/tmp/evsim_cli_navigation_" + std::to_string(seed) + ".csv";
    const Outcome o = evsim(
        "bench navigation --arch-scenes '' --network-targets 3 --timeout 0.02 "
        "--seed " +
        std::to_string(seed) + " --csv " + csv);
    EXPECT_EQ(o.code, 0) << o.output;
    EXPECT_TRUE(says(o, "network  reached 0 of 3")) << o.output;  // 20 ms: nowhere yet
    std::vector<std::string> targets;
    const auto rows = csvRows(csv);
    EXPECT_EQ(rows.size(), 4u);
    for (size_t i = 1; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i][0], "network");
      const int branchings = std::stoi(rows[i][3]);
      EXPECT_GE(branchings, 3);
      EXPECT_LE(branchings, 6);
      EXPECT_EQ(rows[i][4], "0");
      EXPECT_EQ(rows[i][5], "out of time");
      // The right side's vessels lie beyond the brachiocephalic trunk: the
      // Headhunter's scene runs them.
      const bool right = rows[i][2].rfind("right_", 0) == 0;
      EXPECT_EQ(rows[i][1], right ? "network_navigation_headhunter" : "network_navigation");
      targets.push_back(rows[i][2]);
    }
    return targets;
  };
  const std::vector<std::string> first = draw(1);
  EXPECT_EQ(draw(1), first);  // reproducible
  EXPECT_NE(draw(2), first);  // and the seed's
  const Outcome order = evsim("bench navigation --min-branchings 5 --max-branchings 3");
  EXPECT_EQ(order.code, 2);
  EXPECT_TRUE(says(order, "--min-branchings exceeds --max-branchings")) << order.output;
  const Outcome scene = evsim("bench navigation --arch-scenes carotid --network-targets 0");
  EXPECT_EQ(scene.code, 2);
  EXPECT_TRUE(says(scene, "names no targets")) << scene.output;
}

}  // namespace
}  // namespace evsim

namespace evsim {
namespace {

TEST(EvsimCli, RenderWritesAFramePerPeriodAndTheCameraThatMadeThem) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / "evsim_cli_render";
  fs::remove_all(out);
  // 0.4 s at 10 frames/s: the start and four more; 64 pixels on a 0.3 m
  // detector at 1.2 m: a focal length of 256 px.
  const Outcome render =
      evsim("render free_insertion --duration 0.4 --rate 10 --pixels 64 --out " + out.string());
  ASSERT_EQ(render.code, 0) << render.output;
  EXPECT_TRUE(says(render, "5 frames of 64x64 px"));
  for (int k = 0; k < 5; ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%05d.png", k);
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  std::ifstream info(out / "camera_info.yaml");
  const std::string text((std::istreambuf_iterator<char>(info)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("data: [256, 0, 31.5, 0, 256, 31.5, 0, 0, 1]"), std::string::npos) << text;
  // A label line per frame and device: the header, then 5 frames of the wire.
  std::ifstream labels(out / "frames.csv");
  std::string line;
  int lines = 0;
  while (std::getline(labels, line)) ++lines;
  EXPECT_EQ(lines, 1 + 5);
  fs::remove_all(out);
}

TEST(EvsimCli, RenderRefusesWhatCannotBeImaged) {
  const Outcome vessel = evsim(
      "render carotid --duration 0.1 --out /tmp/evsim_cli_r --inject 0,1 --inject-vessel aorta");
  EXPECT_EQ(vessel.code, 2);
  EXPECT_TRUE(says(vessel, "no vessel named 'aorta'"));
  const Outcome free_space =
      evsim("render free_insertion --duration 0.1 --out /tmp/evsim_cli_r --inject 0,1");
  EXPECT_EQ(free_space.code, 2);
  EXPECT_TRUE(says(free_space, "no vessels"));
  const Outcome angle = evsim("render carotid --out /tmp/evsim_cli_r --lao 120");
  EXPECT_EQ(angle.code, 2);
  EXPECT_TRUE(says(angle, "--lao"));
  const Outcome folder = evsim("render carotid --out /proc/evsim_frames");
  EXPECT_EQ(folder.code, 2);
  EXPECT_TRUE(says(folder, "--out"));
  std::filesystem::remove_all("/tmp/evsim_cli_r");
}

}  // namespace
}  // namespace evsim
