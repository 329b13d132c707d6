// Typed access to YAML nodes with errors (LoadError) that name the file, the
// line and the field. Declared and documented in
// endovascular_sim/scene/yaml_reader.h.
#include "endovascular_sim/scene/yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <vector>

#include "endovascular_sim/core/edit_distance.h"
#include "endovascular_sim/core/load_error.h"

namespace evsim {

YAML::Node YamlReader::load() const {
  std::ifstream in;
  if (!from_text_) {
    in.open(file_);
    if (!in) throw LoadError(file_, 0, "", "cannot open the file");
  }
  try {
    return from_text_ ? YAML::Load(text_) : YAML::Load(in);
  } catch (const YAML::ParserException& e) {
    throw LoadError(file_, e.mark.line + 1, "", "malformed YAML: " + e.msg);
  }
}

void YamlReader::fail(const YAML::Node& node, const std::string& field,
                      const std::string& what) const {
  const int line = node.IsDefined() ? node.Mark().line + 1 : 0;
  throw LoadError(file_, line > 0 ? line : 0, field, what);
}

YAML::Node YamlReader::required(const YAML::Node& parent, const std::string& key,
                                const std::string& field) const {
  const YAML::Node n = parent[key];
  if (!n) fail(parent, field, "is missing");
  return n;
}

double YamlReader::number(const YAML::Node& n, const std::string& field) const {
  double v;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(n, field, "must be a number");
  }
  if (!std::isfinite(v)) fail(n, field, "must be finite");
  return v;
}

double YamlReader::number(const YAML::Node& parent, const std::string& key,
                          const std::string& prefix, double fallback) const {
  const YAML::Node n = parent[key];
  return n ? number(n, prefix + key) : fallback;
}

int YamlReader::integer(const YAML::Node& n, const std::string& field) const {
  try {
    return n.as<int>();
  } catch (const YAML::Exception&) {
    fail(n, field, "must be a whole number");
  }
}

std::string YamlReader::text(const YAML::Node& n, const std::string& field) const {
  if (!n.IsScalar()) fail(n, field, "must be a string");
  return n.as<std::string>();
}

void YamlReader::keys(const YAML::Node& n, const std::string& field,
                      std::initializer_list<const char*> allowed) const {
  keys(n, field, std::vector<std::string>(allowed.begin(), allowed.end()));
}

void YamlReader::keys(const YAML::Node& n, const std::string& field,
                      const std::vector<std::string>& allowed) const {
  if (!n.IsMap()) fail(n, field, "must be a map");
  std::set<std::string> seen;
  for (const auto& entry : n) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : "";
    const std::string where = field.empty() ? key : field + "." + key;
    if (key.empty()) fail(entry.first, field, "a key must be a name");
    if (!seen.insert(key).second) fail(entry.first, where, "duplicate key '" + key + "'");
    std::string nearest, list;
    size_t best = std::string::npos;
    bool known = false;
    for (const std::string& a : allowed) {
      known = known || key == a;
      list += (list.empty() ? "" : ", ") + a;
      const size_t d = editDistance(key, a);
      if (d < best) {
        best = d;
        nearest = a;
      }
    }
    if (known) continue;
    std::string what = "unknown key '" + key + "'";
    if (best <= std::max<size_t>(2, key.size() / 3)) what += " (did you mean '" + nearest + "'?)";
    fail(entry.first, where, what + "; known here: " + list);
  }
}

Vec3 YamlReader::vector3(const YAML::Node& n, const std::string& field) const {
  if (!n.IsSequence() || n.size() != 3) fail(n, field, "must be a list of 3 numbers");
  return Vec3(number(n[0], field), number(n[1], field), number(n[2], field));
}

}  // namespace evsim
