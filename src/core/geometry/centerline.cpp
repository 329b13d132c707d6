// Vessel centrelines: a forest of points with radii, read from SWC files.
// Declared and documented in endovascular_sim/geometry/centerline.h.
#include "endovascular_sim/geometry/centerline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/patient_frame.h"

namespace evsim {

int Centerline::numSegments() const {
  int n = 0;
  for (int p : parent) n += p >= 0;
  return n;
}

void Centerline::append(const Centerline& other) {
  const int offset = numPoints();
  const int name_offset = static_cast<int>(vessel_names.size());
  nameVessels(this);
  Centerline named = other;
  nameVessels(&named);
  for (int i = 0; i < other.numPoints(); ++i) {
    position.push_back(other.position[i]);
    radius.push_back(other.radius[i]);
    parent.push_back(other.parent[i] < 0 ? -1 : other.parent[i] + offset);
    type.push_back(other.type[i]);
    vessel.push_back(named.vessel[i] + name_offset);
  }
  for (const std::string& name : named.vessel_names) {
    std::string unique = name;
    for (int k = 2;
         std::find(vessel_names.begin(), vessel_names.end(), unique) != vessel_names.end(); ++k)
      unique = name + "_" + std::to_string(k);
    vessel_names.push_back(unique);
  }
}

bool isVesselName(const std::string& name) {
  if (name.empty() || !(name[0] >= 'a' && name[0] <= 'z')) return false;
  for (char ch : name)
    if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_')) return false;
  return true;
}

void nameVessels(Centerline* c) {
  const int n = c->numPoints();
  c->vessel.resize(n, -1);
  for (int i = 0; i < n; ++i) {
    if (c->vessel[i] >= 0) continue;
    std::vector<int> walk;  // up to a point with a vessel, or a root
    int j = i;
    while (j >= 0 && c->vessel[j] < 0 && static_cast<int>(walk.size()) <= n) {
      walk.push_back(j);
      j = c->parent[j];
    }
    int v = j >= 0 ? c->vessel[j] : -1;
    if (v < 0) {  // a root without a name
      std::string name = "vessel_" + std::to_string(walk.back() + 1);
      while (std::find(c->vessel_names.begin(), c->vessel_names.end(), name) !=
             c->vessel_names.end())
        name += "_";
      v = static_cast<int>(c->vessel_names.size());
      c->vessel_names.push_back(name);
    }
    for (int k : walk) c->vessel[k] = v;
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

namespace {

/// A point line of an SWC file, as written (ids, file unit).
struct SwcRow {
  long id, parent;
  int type, line;
  Vec3 x;
  double r;
};

/// A `# vessel: NAME ID` line.
struct SwcVesselStart {
  std::string name;
  long id;
  int line;
};

/// What an SWC file holds: its points, its named vessels, its unit [m].
struct SwcFile {
  std::vector<SwcRow> rows;
  std::vector<SwcVesselStart> starts;
  double unit{1.0};
  std::string frame;  // its `# frame:` orientation code ("": none)
  int lines{0};
};

/// A comment's `units:`, `frame:` or `vessel:` (anything else is a comment).
void readSwcComment(const std::string& comment_text, const std::string& path, int line,
                    SwcFile* f) {
  std::istringstream comment(comment_text);
  std::string key, value;
  if (comment >> key >> value && key == "units:") f->unit = unitFromName(value, path, line);
  if (key == "frame:") {
    const std::string why = frameCodeProblem(value);
    if (!why.empty()) throw LoadError(path, line, "frame", why);
    f->frame = value;
  }
  if (key != "vessel:") return;
  std::string id_text, rest;
  comment >> id_text;
  char* end = nullptr;
  const long id = std::strtol(id_text.c_str(), &end, 10);
  if (!isVesselName(value))
    throw LoadError(path, line, "vessel",
                    "'" + value + "' is not a vessel name (snake_case: [a-z][a-z0-9_]*)");
  if (id_text.empty() || *end != '\0' || (comment >> rest))
    throw LoadError(path, line, "vessel", "needs '# vessel: NAME ID' (ID: its first point)");
  for (const SwcVesselStart& v : f->starts)
    if (v.name == value)
      throw LoadError(
          path, line, "vessel",
          "'" + value + "' is named twice (also on line " + std::to_string(v.line) + ")");
  f->starts.push_back({value, id, line});
}

/// A point line's 7 columns, each a finite number (id, type and parent whole).
SwcRow readSwcRow(const std::vector<std::string>& tokens, const std::string& path, int line) {
  static const char* kColumns[] = {"id", "type", "x", "y", "z", "radius", "parent"};
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
  return {static_cast<long>(v[0]), static_cast<long>(v[6]),
          static_cast<int>(v[1]),  line,
          Vec3(v[2], v[3], v[4]),  v[5]};
}

SwcFile readSwcFile(const std::string& path, double default_unit) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the centreline file");
  SwcFile f;
  f.unit = default_unit;
  std::string text;
  std::vector<LoadError> problems;  // every line's, at once
  while (std::getline(in, text)) {
    const int line = ++f.lines;
    try {
      const size_t hash = text.find('#');
      if (hash != std::string::npos) {
        readSwcComment(text.substr(hash + 1), path, line, &f);
        text = text.substr(0, hash);
      }
      std::istringstream fields(text);
      std::vector<std::string> tokens;
      for (std::string t; fields >> t;) tokens.push_back(t);
      if (!tokens.empty()) f.rows.push_back(readSwcRow(tokens, path, line));
    } catch (const LoadError& e) {
      if (problems.size() < 100) problems.push_back(e);  // a binary file: the first 100
    }
  }
  throwLoadErrors(problems);
  if (f.rows.empty()) throw LoadError(path, f.lines, "", "the file has no points");
  return f;
}

/// Points in file order, parents as indices, in metres; each within the
/// largest vessel radius and 10 m of the origin.
Centerline swcPoints(const SwcFile& f, const std::unordered_map<long, int>& index,
                     const std::string& path) {
  Centerline c;
  for (const SwcRow& r : f.rows) {
    int parent = -1;
    if (r.parent >= 0) {
      const auto it = index.find(r.parent);
      if (it == index.end())
        throw LoadError(path, r.line, "parent", "no point with id " + std::to_string(r.parent));
      parent = it->second;
      if (parent == static_cast<int>(c.position.size()))
        throw LoadError(path, r.line, "parent", "a point cannot be its own parent");
    }
    if (f.unit * r.r > kMaxVesselRadius) {
      std::ostringstream why;
      why << f.unit * r.r << " m is beyond the largest vessel radius (" << kMaxVesselRadius
          << " m): check the units";
      throw LoadError(path, r.line, "radius", why.str());
    }
    if ((f.unit * r.x).cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw LoadError(path, r.line, "x", "a coordinate beyond 10 m: check the units");
    c.position.push_back(f.unit * r.x);
    c.radius.push_back(f.unit * r.r);
    c.parent.push_back(parent);
    c.type.push_back(r.type);
  }
  return c;
}

/// Refuses parents that form a cycle (a walk up longer than the points).
void checkNoCycle(const Centerline& c, const SwcFile& f, const std::string& path) {
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
      throw LoadError(path, f.rows[j].line, "parent",
                      "the parents form a cycle through id " + std::to_string(f.rows[j].id));
    for (int k : walk) state[k] = 2;
  }
}

}  // namespace

Centerline loadCenterlineFile(const std::string& path, double default_unit) {
  const SwcFile f = readSwcFile(path, default_unit);
  std::unordered_map<long, int> index;
  for (size_t i = 0; i < f.rows.size(); ++i)
    if (!index.emplace(f.rows[i].id, static_cast<int>(i)).second)
      throw LoadError(path, f.rows[i].line, "id",
                      "id " + std::to_string(f.rows[i].id) + " appears twice");
  Centerline c = swcPoints(f, index, path);
  c.frame = f.frame;
  c.vessel.assign(c.numPoints(), -1);
  for (const SwcVesselStart& v : f.starts) {
    const auto it = index.find(v.id);
    if (it == index.end())
      throw LoadError(path, v.line, "vessel", "no point with id " + std::to_string(v.id));
    if (c.vessel[it->second] >= 0)
      throw LoadError(path, v.line, "vessel",
                      "point " + std::to_string(v.id) + " already starts vessel '" +
                          c.vessel_names[c.vessel[it->second]] + "'");
    c.vessel[it->second] = static_cast<int>(c.vessel_names.size());
    c.vessel_names.push_back(v.name);
  }
  checkNoCycle(c, f, path);
  nameVessels(&c);
  return c;
}

void saveCenterlineFile(const Centerline& c, const std::string& path, const std::string& comment) {
  std::ofstream out(path);
  std::istringstream lines(comment);
  for (std::string l; std::getline(lines, l);) out << "# " << l << "\n";
  out << "# units: mm\n";
  if (!c.frame.empty()) out << "# frame: " << c.frame << "\n";
  Centerline named = c;
  nameVessels(&named);
  for (int i = 0; i < named.numPoints(); ++i) {
    const int p = named.parent[i];
    if (p < 0 || named.vessel[p] != named.vessel[i])
      out << "# vessel: " << named.vessel_names[named.vessel[i]] << " " << i + 1 << "\n";
  }
  out << "# id type x y z radius parent\n";
  char buf[160];
  for (int i = 0; i < c.numPoints(); ++i) {
    const Vec3 x = 1e3 * c.position[i];
    std::snprintf(buf, sizeof(buf), "%d %d %.4f %.4f %.4f %.4f %d\n", i + 1, c.type[i], x.x(),
                  x.y(), x.z(), 1e3 * c.radius[i], c.parent[i] < 0 ? -1 : c.parent[i] + 1);
    out << buf;
  }
}

}  // namespace evsim
