// The input fuzz test: from every shipped scene, device, centreline (SWC
// and VTK) and from saved state files, a seeded generator derives variants
// (lines deleted, duplicated, swapped or shifted; keys misspelled; numbers
// made NaN, infinite, huge, negative, zero or text; scalars swapped with
// maps and lists; the file truncated, garbage bytes inserted, emptied) and
// runs `evsim` on each as a user would: `run VARIANT --steps 20` for a
// scene, `check` for a device or a centreline, `run SCENE --load-state
// VARIANT` for a state file. Each must end with a clear error (exit 2, or
// exit 1 for a step that fails, with an "evsim: " message and no "internal
// error") or a valid run (exit 0): never a signal, never past the time
// limit, never above 2 GiB of memory.
//
// Repeat with another draw: EVSIM_FUZZ_SEED=N; more cases: EVSIM_FUZZ_SCALE=4.
// Under the sanitizers: docs/testing.md ("Fuzzing").
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace evsim {
namespace {

namespace fs = std::filesystem;

constexpr double kTimeLimit = 30.0;           // [s] per case
constexpr long kMemoryLimitKiB = 2L << 20;    // 2 GiB of resident memory
constexpr rlim_t kAddressSpace = 8ULL << 30;  // the child cannot map more than 8 GiB

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

/// A number of the text (a run of digits, or a minus, not inside a word)
/// replaced by one of kNumbers: NaN, infinities, extremes, a word, a list.
std::string replaceANumber(const std::string& text, std::mt19937_64& rng, std::string* what) {
  auto pick = [&](size_t n) { return n == 0 ? 0 : static_cast<size_t>(rng() % n); };
  static const char* kNumbers[] = {
      "nan",    "inf",    "-inf",   "1e308",      "-1e308",
      "0",      "-1",     "1e-300", "4294967297", "abc",
      "[1, 2]", "{a: 1}", "",       "-0.0000001", "99999999999999999999"};
  std::vector<size_t> starts;
  for (size_t i = 0; i < text.size(); ++i)
    if ((std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '-') &&
        (i == 0 || !std::isalnum(static_cast<unsigned char>(text[i - 1]))))
      starts.push_back(i);
  if (starts.empty()) return text;
  const size_t s = starts[pick(starts.size())];
  size_t e = s + 1;
  while (e < text.size() && (std::isalnum(static_cast<unsigned char>(text[e])) || text[e] == '.' ||
                             text[e] == '-' || text[e] == '+'))
    ++e;
  const std::string by = kNumbers[pick(sizeof(kNumbers) / sizeof(kNumbers[0]))];
  *what = "the number '" + text.substr(s, e - s) + "' made '" + by + "'";
  return text.substr(0, s) + by + text.substr(e);
}

/// One mutation of a text file, drawn from rng; *what says which.
std::string mutate(const std::string& text, std::mt19937_64& rng, std::string* what) {
  std::vector<std::string> lines = splitLines(text);
  auto pick = [&](size_t n) { return n == 0 ? 0 : static_cast<size_t>(rng() % n); };
  const size_t at = pick(lines.size());
  switch (rng() % 11) {
    case 0:
      *what = "line " + std::to_string(at + 1) + " deleted";
      if (!lines.empty()) lines.erase(lines.begin() + at);
      return joinLines(lines);
    case 1:
      *what = "line " + std::to_string(at + 1) + " duplicated";
      if (!lines.empty()) lines.insert(lines.begin() + at, lines[at]);
      return joinLines(lines);
    case 2: {  // two letters of a key (YAML) or an attribute (XML) swapped
      *what = "a key misspelled on line " + std::to_string(at + 1);
      if (lines.empty()) return text;
      std::string& l = lines[at];
      const size_t end = std::min(l.find(':'), l.find('='));
      if (end == std::string::npos || end < 2) return joinLines(lines);
      const size_t k = 1 + pick(end - 1);
      std::swap(l[k - 1], l[k]);
      return joinLines(lines);
    }
    case 3:
    case 4:
      return replaceANumber(text, rng, what);
    case 5: {  // a value's type swapped
      static const char* kValues[] = {"{x: 1}", "[1, 2, 3]", "text", "~", "[]", "{}", "[[1]]"};
      if (lines.empty()) return text;
      std::string& l = lines[at];
      const size_t colon = l.find(": ");
      const std::string by = kValues[pick(sizeof(kValues) / sizeof(kValues[0]))];
      *what = "the value on line " + std::to_string(at + 1) + " made '" + by + "'";
      if (colon == std::string::npos) return joinLines(lines);
      l = l.substr(0, colon + 2) + by;
      return joinLines(lines);
    }
    case 6: {
      const size_t cut = pick(text.size() + 1);
      *what = "truncated at byte " + std::to_string(cut);
      return text.substr(0, cut);
    }
    case 7: {
      const size_t pos = pick(text.size() + 1);
      std::string garbage;
      for (size_t k = 1 + pick(16); k > 0; --k) garbage += static_cast<char>(rng() % 256);
      *what = std::to_string(garbage.size()) + " garbage bytes at byte " + std::to_string(pos);
      return text.substr(0, pos) + garbage + text.substr(pos);
    }
    case 8:
      *what = "line " + std::to_string(at + 1) + " shifted";
      if (lines.empty()) return text;
      if (rng() % 2)
        lines[at] = "  " + lines[at];
      else if (lines[at].rfind("  ", 0) == 0)
        lines[at] = lines[at].substr(2);
      return joinLines(lines);
    case 9: {
      const size_t other = pick(lines.size());
      *what = "lines " + std::to_string(at + 1) + " and " + std::to_string(other + 1) + " swapped";
      if (!lines.empty()) std::swap(lines[at], lines[other]);
      return joinLines(lines);
    }
    default:
      *what = "emptied";
      return "";
  }
}

struct Case {
  std::string label;              // base file and mutation
  std::vector<std::string> args;  // evsim's arguments
  std::string log;                // its output
};

struct Running {
  pid_t pid;
  size_t index;
  std::chrono::steady_clock::time_point start;
};

struct Verdict {
  int finished{0}, valid{0}, refused{0}, step_failed{0};
  std::vector<std::string> failures;
};

pid_t launch(const Case& c) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
#if !defined(__SANITIZE_ADDRESS__)  // AddressSanitizer reserves terabytes of shadow space
  const rlimit as{kAddressSpace, kAddressSpace};
  setrlimit(RLIMIT_AS, &as);
#endif
  const rlimit core{0, 0};
  setrlimit(RLIMIT_CORE, &core);
  std::FILE* out = std::freopen(c.log.c_str(), "w", stdout);
  if (!out || dup2(fileno(stdout), STDERR_FILENO) < 0) _exit(99);
  std::vector<char*> argv{const_cast<char*>(EVSIM_EVSIM_BINARY)};
  for (const std::string& a : c.args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  execv(EVSIM_EVSIM_BINARY, argv.data());
  _exit(98);
}

void judge(const Case& c, int status, const rusage& use, double seconds, Verdict* v) {
  ++v->finished;
  const std::string out = readFile(c.log);
  std::string failure;
  if (WIFSIGNALED(status)) {
    failure = "killed by signal " + std::to_string(WTERMSIG(status));
  } else if (use.ru_maxrss > kMemoryLimitKiB) {
    failure = "used " + std::to_string(use.ru_maxrss >> 10) + " MiB";
  } else {
    const int code = WEXITSTATUS(status);
    // A clear error: evsim's own message, or `check`'s line naming the file.
    bool message = out.find("evsim: ") != std::string::npos;
    for (const std::string& a : c.args)
      message = message || (a.find('/') != std::string::npos && out.rfind(a + ":", 0) == 0);
    if (code == 0) {
      ++v->valid;
    } else if ((code == 1 || code == 2) && message &&
               out.find("internal error") == std::string::npos) {
      ++(code == 2 ? v->refused : v->step_failed);
    } else {
      failure = "exit " + std::to_string(code) + " with: " + out.substr(0, 300);
    }
  }
  if (seconds > kTimeLimit) failure = "took " + std::to_string(seconds) + " s";
  if (failure.empty()) return;
  std::string command = "evsim";
  for (const std::string& a : c.args) command += " " + a;
  v->failures.push_back(c.label + " (" + command + "): " + failure);
}

/// Runs the cases two at a time.
Verdict runAll(std::vector<Case>& cases) {
  Verdict v;
  std::vector<Running> running;
  size_t next = 0;
  while (next < cases.size() || !running.empty()) {
    while (running.size() < 2 && next < cases.size()) {
      running.push_back({launch(cases[next]), next, std::chrono::steady_clock::now()});
      ++next;
    }
    bool reaped = false;
    for (size_t k = 0; k < running.size(); ++k) {
      int status = 0;
      rusage use{};
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - running[k].start)
              .count();
      pid_t done = wait4(running[k].pid, &status, WNOHANG, &use);
      if (done == 0 && seconds > kTimeLimit) {
        kill(running[k].pid, SIGKILL);
        done = wait4(running[k].pid, &status, 0, &use);
      }
      if (done != running[k].pid) continue;
      judge(cases[running[k].index], status, use, seconds, &v);
      running.erase(running.begin() + k);
      reaped = true;
      break;
    }
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return v;
}

TEST(Fuzz, NoInputAbortsHangsOrRunsAwayWithMemory) {
  const char* seed_text = std::getenv("EVSIM_FUZZ_SEED");
  const char* scale_text = std::getenv("EVSIM_FUZZ_SCALE");
  const uint64_t seed = seed_text ? std::strtoull(seed_text, nullptr, 10) : 20261126;
  const double scale = scale_text ? std::atof(scale_text) : 1.0;
  std::mt19937_64 rng(seed);
  const fs::path config = EVSIM_CONFIG_DIR;
  const fs::path dir = fs::temp_directory_path() / ("evsim_fuzz_" + std::to_string(getpid()));
  fs::remove_all(dir);
  for (const char* sub : {"scenes", "files", "logs"}) fs::create_directories(dir / sub);
  // The scenes' relative paths (../devices, ../vessels) resolve from dir/scenes.
  fs::create_directory_symlink(config / "devices", dir / "devices");
  fs::create_directory_symlink(config / "vessels", dir / "vessels");

  // Two saved states to damage: one device with self-contact, two coaxial with friction.
  for (const char* scene : {"aneurysm", "carotid_catheter"}) {
    const std::string cmd = std::string(EVSIM_EVSIM_BINARY) + " run " + scene +
                            " --steps 300 --save-state " + (dir / "files").string() + "/" + scene +
                            ".state > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }

  std::vector<Case> cases;
  auto derive = [&](const fs::path& base, int count, const std::string& folder,
                    const std::string& ext, auto args_for) {
    const std::string text = readFile(base);
    for (int k = 0; k < static_cast<int>(count * scale); ++k) {
      std::string what;
      const std::string variant = mutate(text, rng, &what);
      const fs::path path = dir / folder / (base.stem().string() + "_" + std::to_string(k) + ext);
      std::ofstream(path, std::ios::binary) << variant;
      Case c;
      c.label = base.filename().string() + ": " + what;
      c.args = args_for(path.string());
      c.log = (dir / "logs" / (std::to_string(cases.size()) + ".txt")).string();
      cases.push_back(c);
    }
  };
  for (const auto& e : fs::directory_iterator(config / "scenes")) {
    if (e.path().extension() != ".yaml") continue;
    const std::string name = e.path().stem().string();
    const bool heavy = name.rfind("network", 0) == 0;  // 4,000 vessels: a second per build
    derive(e.path(), heavy ? 12 : 90, "scenes", ".yaml", [](const std::string& p) {
      return std::vector<std::string>{"run", p, "--steps", "20"};
    });
  }
  for (const auto& e : fs::directory_iterator(config / "devices"))
    if (e.path().extension() == ".urdf")
      derive(e.path(), 50, "files", ".urdf", [](const std::string& p) {
        return std::vector<std::string>{"check", p};
      });
  for (const auto& e : fs::directory_iterator(config / "vessels")) {
    if (e.path().extension() == ".swc")
      derive(e.path(), 50, "files", ".swc", [](const std::string& p) {
        return std::vector<std::string>{"check", p};
      });
    if (e.path().extension() == ".vtp")
      derive(e.path(), 40, "files", ".vtp", [](const std::string& p) {
        return std::vector<std::string>{"check", p, "--units", "mm"};
      });
  }
  for (const char* scene : {"aneurysm", "carotid_catheter"})
    derive(dir / "files" / (std::string(scene) + ".state"), 60, "files", ".txt",
           [scene](const std::string& p) {
             return std::vector<std::string>{"run", scene, "--load-state", p, "--steps", "5"};
           });

  const auto t0 = std::chrono::steady_clock::now();
  Verdict v = runAll(cases);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "[ metric   ] fuzz seed %llu: %zu variants in %.0f s: %d valid runs, %d refused (exit 2), "
      "%d with a failed step (exit 1), %zu failures\n",
      static_cast<unsigned long long>(seed), cases.size(), s, v.valid, v.refused, v.step_failed,
      v.failures.size());
  EXPECT_GE(cases.size(), 2000u * scale);
  EXPECT_EQ(v.finished, static_cast<int>(cases.size()));
  for (size_t k = 0; k < v.failures.size() && k < 20; ++k) ADD_FAILURE() << v.failures[k];
  if (v.failures.empty()) fs::remove_all(dir);
}

}  // namespace
}  // namespace evsim
