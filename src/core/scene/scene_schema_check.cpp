// A parsed scene file against the schema (scene/scene_schema.h): every
// problem at once, with its line and column, for the loader and
// `evsim check`; and the schema as the Markdown reference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <sstream>

#include "endovascular_sim/core/edit_distance.h"
#include "endovascular_sim/core/number_text.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/scene/scene_schema.h"

namespace evsim {
namespace {

/// "[0, 0.04] s", "(0, 1]", "at least 1e-5 m"; "" without bounds.
std::string rangeText(const SchemaEntry& e) {
  return evsim::rangeText(e.min, e.max, e.min_open, e.max_open, e.unit);
}

bool inRange(const SchemaEntry& e, double v) {
  return evsim::inRange(v, e.min, e.max, e.min_open, e.max_open);
}

std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// " (did you mean 'x'?)" when one of `names` is close to `name`.
std::string suggestion(const std::string& name, const std::vector<std::string>& names) {
  std::string nearest;
  size_t best = std::string::npos;
  for (const std::string& n : names) {
    const size_t d = editDistance(name, n);
    if (d < best) best = d, nearest = n;
  }
  return best <= std::max<size_t>(2, name.size() / 3) ? " (did you mean '" + nearest + "'?)" : "";
}

/// The key a schema entry is listed under in its parent map ("" for a
/// list's item entry), and the parent's path.
std::string parentOf(const std::string& path) {
  if (path.size() > 2 && path.compare(path.size() - 2, 2, "[]") == 0)
    return path.substr(0, path.size() - 2);
  const size_t dot = path.rfind('.');
  return dot == std::string::npos ? "" : path.substr(0, dot);
}
bool isItem(const std::string& path) {
  return path.size() > 2 && path.compare(path.size() - 2, 2, "[]") == 0;
}
std::string nameOf(const std::string& path) {
  const size_t dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

/// How a type is named in the reference table and in an error message.
struct TypeWords {
  std::string table, message;
};
TypeWords typeWords(SchemaType t, const SchemaEntry& e) {
  switch (t) {
    case SchemaType::kMap:
      return {"map", "a map"};
    case SchemaType::kList:
      return {"list", "a list"};
    case SchemaType::kNumber:
      return {"number", "a number"};
    case SchemaType::kInteger:
      return {"integer", "a whole number"};
    case SchemaType::kBool:
      return {"bool", "true or false"};
    case SchemaType::kText:
      return {"string", "a string"};
    case SchemaType::kChoice:
      return {list(e.choices), (e.choices.size() == 1 ? "" : "one of ") + list(e.choices)};
    case SchemaType::kVector3:
      return {"[x, y, z]", "a list of 3 numbers"};
    case SchemaType::kIdNames:
      return {"{id: name}", "a map of branch ids to vessel names"};
    default:
      return {"", "absent"};
  }
}

class Checker {
 public:
  Checker() {
    for (const SchemaEntry& e : sceneSchema()) {
      by_path_[e.path] = &e;
      if (!isItem(e.path)) children_[parentOf(e.path)].push_back(&e);
    }
  }

  void map(const YAML::Node& n, const std::string& schema_path, const std::string& shown) {
    std::vector<std::string> names;
    for (const SchemaEntry* c : children_[schema_path]) names.push_back(nameOf(c->path));
    std::set<std::string> seen;
    for (const auto& kv : n) {
      if (!kv.first.IsScalar()) {
        add(kv.first, shown, "a key must be a name");
        continue;
      }
      const std::string name = kv.first.Scalar();
      const std::string key = shown.empty() ? name : shown + "." + name;
      if (!seen.insert(name).second) {
        add(kv.first, key, "duplicate key '" + name + "'");
        continue;
      }
      const auto it = by_path_.find(schema_path.empty() ? name : schema_path + "." + name);
      if (const RetiredKey* retired =
              findRetiredKey(schema_path.empty() ? name : schema_path + "." + name)) {
        add(kv.first, key, retired->why);
        continue;
      }
      if (it == by_path_.end() || isItem(it->first)) {
        add(kv.first, key,
            "unknown key '" + name + "'" + suggestion(name, names) +
                "; known here: " + list(names));
        continue;
      }
      value(kv.second, *it->second, key);
    }
    for (const SchemaEntry* c : children_[schema_path])
      if (c->required && !seen.count(nameOf(c->path)))
        add(n, shown.empty() ? nameOf(c->path) : shown + "." + nameOf(c->path), "is missing");
  }

  void value(const YAML::Node& v, const SchemaEntry& e, const std::string& key) {
    // A word among a number's alternatives (`max_force: unlimited`).
    if (e.alternative == SchemaType::kChoice && v.IsScalar() &&
        std::find(e.choices.begin(), e.choices.end(), v.Scalar()) != e.choices.end())
      return;
    if (fits(v, e.type)) return deep(v, e, e.type, key);
    if (e.alternative != SchemaType::kNone && fits(v, e.alternative))
      return deep(v, e, e.alternative, key);
    add(v, key,
        "must be " + typeWords(e.type, e).message +
            (e.alternative != SchemaType::kNone ? " or " + typeWords(e.alternative, e).message
                                                : ""));
  }

  std::vector<SchemaProblem> problems;

 private:
  static bool fits(const YAML::Node& v, SchemaType t) {
    switch (t) {
      case SchemaType::kMap:
      case SchemaType::kIdNames:
        return v.IsMap();
      case SchemaType::kList:
        return v.IsSequence();
      case SchemaType::kVector3:
        return v.IsSequence();
      case SchemaType::kNone:
        return false;
      default:
        return v.IsScalar();
    }
  }

  void deep(const YAML::Node& v, const SchemaEntry& e, SchemaType t, const std::string& key) {
    switch (t) {
      case SchemaType::kMap:
        return map(v, e.path, key);
      case SchemaType::kList: {
        const auto item = by_path_.find(e.path + "[]");
        if (item == by_path_.end()) return;
        for (size_t i = 0; i < v.size(); ++i)
          value(v[i], *item->second, key + "[" + std::to_string(i) + "]");
        return;
      }
      case SchemaType::kNumber:
      case SchemaType::kInteger:
        return scalarNumber(v, e, t == SchemaType::kInteger, key);
      case SchemaType::kBool:
        if (v.Scalar() != "true" && v.Scalar() != "false")
          add(v, key,
              e.type == SchemaType::kMap ? "must be true, false or a map"
                                         : "must be true or false");
        return;
      case SchemaType::kChoice:
        for (const std::string& c : e.choices)
          if (v.Scalar() == c) return;
        add(v, key,
            "'" + v.Scalar() + "' must be one of " + list(e.choices) +
                suggestion(v.Scalar(), e.choices));
        return;
      case SchemaType::kVector3:
        if (v.size() != 3) return add(v, key, "must be a list of 3 numbers");
        for (size_t i = 0; i < 3; ++i) {
          double x = 0.0;
          if (!v[i].IsScalar() || !parse(v[i], &x) || !std::isfinite(x))
            return add(v[i], key, "must be a list of 3 finite numbers");
        }
        return;
      case SchemaType::kIdNames:
        for (const auto& kv : v) {
          double id = -1.0;
          if (!kv.first.IsScalar() || !parse(kv.first, &id) || id < 0 || id != std::floor(id))
            add(kv.first, key, "a branch id must be a whole number >= 0");
          else if (!kv.second.IsScalar() || !isVesselName(kv.second.Scalar()))
            add(kv.second, key + "." + kv.first.Scalar(),
                "'" + (kv.second.IsScalar() ? kv.second.Scalar() : std::string("?")) +
                    "' is not a vessel name ([a-z][a-z0-9_]*)");
        }
        return;
      default:
        return;  // kText: any scalar
    }
  }

  static bool parse(const YAML::Node& v, double* x) {
    try {
      *x = v.as<double>();
      return true;
    } catch (const YAML::Exception&) {
      return false;
    }
  }

  void scalarNumber(const YAML::Node& v, const SchemaEntry& e, bool whole, const std::string& key) {
    double x = 0.0;
    if (!parse(v, &x)) {
      std::string what = whole ? "must be a whole number" : "must be a number";
      if (e.alternative == SchemaType::kChoice)
        what +=
            " or " + typeWords(SchemaType::kChoice, e).message + suggestion(v.Scalar(), e.choices);
      return add(v, key, what);
    }
    if (!std::isfinite(x)) return add(v, key, "must be finite");
    if (whole && (x != std::floor(x) || std::abs(x) > 1e15))
      return add(v, key, "must be a whole number");
    if (!inRange(e, x))
      add(v, key,
          (std::isfinite(e.min) && std::isfinite(e.max) ? "must lie in " : "must be ") +
              rangeText(e) + ", got " + v.Scalar());
  }

  void add(const YAML::Node& at, const std::string& key, const std::string& what) {
    SchemaProblem p;
    p.key = key;
    p.what = what;
    if (at.IsDefined() && !at.Mark().is_null()) {
      p.line = at.Mark().line + 1;
      p.column = at.Mark().column + 1;
    }
    problems.push_back(p);
  }

  std::map<std::string, const SchemaEntry*> by_path_;
  std::map<std::string, std::vector<const SchemaEntry*>> children_;
};

std::string typeName(const SchemaEntry& e) {
  auto one = [&](SchemaType t) { return typeWords(t, e).table; };
  return one(e.type) + (e.alternative != SchemaType::kNone ? " or " + one(e.alternative) : "");
}

}  // namespace

std::vector<SchemaProblem> checkSceneSchema(const YAML::Node& root) {
  Checker c;
  if (!root.IsMap()) {
    SchemaProblem p;
    p.what = root.IsNull() ? "the file is empty: a scene is a YAML map" : "a scene is a YAML map";
    if (root.IsDefined() && !root.Mark().is_null()) p.line = root.Mark().line + 1;
    return {p};
  }
  c.map(root, "", "");
  return c.problems;
}

std::string formatProblem(const std::string& file, const SchemaProblem& p) {
  std::ostringstream s;
  s << file << ":" << p.line << ":" << p.column << ": " << (p.key.empty() ? "" : p.key + ": ")
    << p.what;
  return s.str();
}

std::string sceneSchemaMarkdown() {
  std::ostringstream s;
  s << "| key | type | unit | default | range | meaning |\n| --- | --- | --- | --- | --- | --- |\n";
  for (const SchemaEntry& e : sceneSchema()) {
    std::string range = rangeText(e);
    if (!e.unit.empty() && range.size() > e.unit.size())
      range = range.substr(0, range.size() - e.unit.size() - 1);  // the unit has its column
    s << "| `" << e.path << "` | " << typeName(e) << " | " << e.unit << " | "
      << (e.required ? "required" : e.fallback) << " | " << range << " | " << e.meaning << " |\n";
  }
  return s.str();
}

}  // namespace evsim
