#include "endovascular_sim/geometry/centerline.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "endovascular_sim/core/load_error.h"

namespace evsim {

int Centerline::numSegments() const {
  int n = 0;
  for (int p : parent) n += p >= 0;
  return n;
}

void Centerline::append(const Centerline& other) {
  const int offset = numPoints();
  for (int i = 0; i < other.numPoints(); ++i) {
    position.push_back(other.position[i]);
    radius.push_back(other.radius[i]);
    parent.push_back(other.parent[i] < 0 ? -1 : other.parent[i] + offset);
    type.push_back(other.type[i]);
  }
}

namespace {

double unitFromName(const std::string& name, const std::string& path, int line) {
  if (name == "m") return 1.0;
  if (name == "mm") return 1e-3;
  if (name == "um") return 1e-6;
  throw LoadError(path, line, "units", "unknown unit '" + name + "' (m, mm or um)");
}

}  // namespace

Centerline loadCenterlineFile(const std::string& path, double default_unit) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the centreline file");
  struct Row {
    long id, parent;
    int type, line;
    Vec3 x;
    double r;
  };
  std::vector<Row> rows;
  double unit = default_unit;
  std::string text;
  int line = 0;
  static const char* kColumns[] = {"id", "type", "x", "y", "z", "radius", "parent"};
  while (std::getline(in, text)) {
    ++line;
    const size_t hash = text.find('#');
    if (hash != std::string::npos) {
      std::istringstream comment(text.substr(hash + 1));
      std::string key, value;
      if (comment >> key >> value && key == "units:") unit = unitFromName(value, path, line);
      text = text.substr(0, hash);
    }
    std::istringstream fields(text);
    std::vector<std::string> tokens;
    for (std::string t; fields >> t;) tokens.push_back(t);
    if (tokens.empty()) continue;
    if (tokens.size() != 7)
      throw LoadError(
          path, line, "",
          "needs 7 columns (id type x y z radius parent), got " + std::to_string(tokens.size()));
    double v[7];
    for (int k = 0; k < 7; ++k) {
      char* end = nullptr;
      v[k] = std::strtod(tokens[k].c_str(), &end);
      if (end == tokens[k].c_str() || *end != '\0')
        throw LoadError(path, line, kColumns[k], "'" + tokens[k] + "' is not a number");
      if (!std::isfinite(v[k])) throw LoadError(path, line, kColumns[k], "must be finite");
    }
    if (v[5] <= 0.0) throw LoadError(path, line, "radius", "must be positive");
    for (int k : {0, 1, 6})  // id, type, parent
      if (v[k] != std::floor(v[k]) || std::abs(v[k]) > 1e15)
        throw LoadError(path, line, kColumns[k], "'" + tokens[k] + "' is not a whole number");
    rows.push_back({static_cast<long>(v[0]), static_cast<long>(v[6]), static_cast<int>(v[1]), line,
                    Vec3(v[2], v[3], v[4]), v[5]});
  }
  if (rows.empty()) throw LoadError(path, line, "", "the file has no points");

  std::unordered_map<long, int> index;
  for (size_t i = 0; i < rows.size(); ++i)
    if (!index.emplace(rows[i].id, static_cast<int>(i)).second)
      throw LoadError(path, rows[i].line, "id",
                      "id " + std::to_string(rows[i].id) + " appears twice");
  Centerline c;
  for (const Row& r : rows) {
    int parent = -1;
    if (r.parent >= 0) {
      const auto it = index.find(r.parent);
      if (it == index.end())
        throw LoadError(path, r.line, "parent", "no point with id " + std::to_string(r.parent));
      parent = it->second;
      if (parent == static_cast<int>(c.position.size()))
        throw LoadError(path, r.line, "parent", "a point cannot be its own parent");
    }
    c.position.push_back(unit * r.x);
    c.radius.push_back(unit * r.r);
    c.parent.push_back(parent);
    c.type.push_back(r.type);
  }
  // Cycles: follow parents; a walk longer than the point count loops.
  std::vector<char> state(c.numPoints(), 0);  // 0 unseen, 1 on the current walk, 2 done
  for (int i = 0; i < c.numPoints(); ++i) {
    std::vector<int> walk;
    int j = i;
    while (j >= 0 && state[j] == 0) {
      state[j] = 1;
      walk.push_back(j);
      j = c.parent[j];
    }
    if (j >= 0 && state[j] == 1)
      throw LoadError(path, rows[j].line, "parent",
                      "the parents form a cycle through id " + std::to_string(rows[j].id));
    for (int k : walk) state[k] = 2;
  }
  return c;
}

void saveCenterlineFile(const Centerline& c, const std::string& path, const std::string& comment) {
  std::ofstream out(path);
  std::istringstream lines(comment);
  for (std::string l; std::getline(lines, l);) out << "# " << l << "\n";
  out << "# units: mm\n# id type x y z radius parent\n";
  char buf[160];
  for (int i = 0; i < c.numPoints(); ++i) {
    const Vec3 x = 1e3 * c.position[i];
    std::snprintf(buf, sizeof(buf), "%d %d %.4f %.4f %.4f %.4f %d\n", i + 1, c.type[i], x.x(),
                  x.y(), x.z(), 1e3 * c.radius[i], c.parent[i] < 0 ? -1 : c.parent[i] + 1);
    out << buf;
  }
}

}  // namespace evsim
