// A step's last LCP written to a file and read back (`evsim run --dump-lcp`):
// W, q, the solver's answer and status, for a failure studied outside the
// simulator. Declared and documented in endovascular_sim/contact/contact_solver.h.
#include <cstdio>
#include <fstream>
#include <string>

#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/core/load_error.h"

namespace evsim {

bool writeLcpRecord(const LcpRecord& r, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const long c = r.q.size();
  std::fprintf(f,
               "# endovascular_sim LCP: w = W z + q, 0 <= z _|_ w >= 0; W [m/N], q [m], z [N]\n");
  std::fprintf(f, "size %ld\nW\n", c);
  for (long i = 0; i < c; ++i)
    for (long j = 0; j < c; ++j) std::fprintf(f, "%.17g%c", r.W(i, j), j + 1 < c ? ' ' : '\n');
  std::fprintf(f, "q\n");
  for (long i = 0; i < c; ++i) std::fprintf(f, "%.17g\n", r.q(i));
  std::fprintf(f, "z\n");
  for (long i = 0; i < c; ++i) std::fprintf(f, "%.17g\n", r.z(i));
  if (r.mu.size() > 0) {
    std::fprintf(f, "mu %ld\n", static_cast<long>(r.mu.size()));
    for (long i = 0; i < r.mu.size(); ++i) std::fprintf(f, "%.17g\n", r.mu(i));
  }
  return std::fclose(f) == 0;
}

LcpRecord readLcpRecord(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the LCP file");
  std::string line, word;
  std::getline(in, line);  // header comment
  long c = -1;
  if (!(in >> word >> c) || word != "size" || c < 0)
    throw LoadError(path, 2, "size", "expected 'size c'");
  LcpRecord r{MatX(c, c), VecX(c), VecX(c), VecX()};
  auto expect = [&](const char* name) {
    if (!(in >> word) || word != name) throw LoadError(path, 0, name, "section missing");
  };
  expect("W");
  for (long i = 0; i < c * c; ++i)
    if (!(in >> r.W(i / c, i % c))) throw LoadError(path, 0, "W", "too few numbers");
  expect("q");
  for (long i = 0; i < c; ++i)
    if (!(in >> r.q(i))) throw LoadError(path, 0, "q", "too few numbers");
  expect("z");
  for (long i = 0; i < c; ++i)
    if (!(in >> r.z(i))) throw LoadError(path, 0, "z", "too few numbers");
  long contacts = 0;
  if (in >> word) {  // friction: "mu k" and k coefficients
    if (word != "mu" || !(in >> contacts) || contacts < 0 || 3 * contacts != c)
      throw LoadError(path, 0, "mu", "expected 'mu c/3'");
    r.mu.resize(contacts);
    for (long i = 0; i < contacts; ++i)
      if (!(in >> r.mu(i))) throw LoadError(path, 0, "mu", "too few numbers");
  }
  return r;
}

}  // namespace evsim
