// The scene format, described once: every key of a scene file with its
// type, unit, default, allowed range and meaning (scene_schema.cpp). The
// loader checks a file against it before reading it (checkSceneSchema: every
// problem at once, with line and column), `evsim check` prints those
// problems, and the key reference in config/scenes/README.md is generated
// from it (`evsim schema`; a test keeps the two equal). What the schema
// cannot say (a device file's content, a vessel name of the tree, devices
// placed through each other) the section readers check after it.
#pragma once

#include <yaml-cpp/yaml.h>

#include <limits>
#include <string>
#include <vector>

namespace evsim {

/// Lengths compared with a device's length (`inserted_length`) agree within
/// this relative tolerance: a device's length is a sum of its sections', so
/// a full insertion written as the nominal length may exceed it by
/// round-off, and is valid.
constexpr double kLengthTolerance = 1e-9;

enum class SchemaType {
  kNone,     // (no alternative)
  kMap,      // a map of the keys below it
  kList,     // a list of the entry `path[]`
  kNumber,   // a finite number
  kInteger,  // a whole number
  kBool,     // true or false
  kText,     // a string
  kChoice,   // one of `choices`
  kVector3,  // [x, y, z]
  kIdNames,  // a map from whole numbers >= 0 to vessel names
};

struct SchemaEntry {
  std::string path;  // "vessels.network.seed"; a list's items: "devices[]", "devices[].file"
  SchemaType type{SchemaType::kNumber};
  SchemaType alternative{SchemaType::kNone};  // another form it may take (`sleep: false`)
  std::string unit;                           // "s", "m", "N m", "" for none
  std::string fallback;                       // the default as written, "" when none
  bool required{false};
  double min{-std::numeric_limits<double>::infinity()};
  double max{std::numeric_limits<double>::infinity()};
  bool min_open{false}, max_open{false};  // (min, ...] or [..., max)
  std::vector<std::string> choices;       // kChoice (or a kChoice alternative)
  std::string meaning;
};

/// The scene format, parents before their keys.
const std::vector<SchemaEntry>& sceneSchema();

/// A key the format no longer has, and what replaced it.
struct RetiredKey {
  std::string path;  // "contact.interior_balls"
  std::string why;   // "... : remove the key"
};

/// Keys a scene may still carry from an older format: refused at load with
/// their `why`, not as unknown keys.
const std::vector<RetiredKey>& retiredSceneKeys();

/// The retired key at `path` ("contact.interior_balls"), or nullptr.
const RetiredKey* findRetiredKey(const std::string& path);

/// One problem of a file against the schema.
struct SchemaProblem {
  int line{0}, column{0};  // 1-based; 0 unknown
  std::string key;         // "devices[1].drive.max_force"
  std::string what;        // "must lie in (0, 100] N, got -1"
};

/// Every problem of a parsed scene file against the schema: unknown keys
/// (with the nearest known one), duplicate keys, missing required keys,
/// wrong types, values out of range.
std::vector<SchemaProblem> checkSceneSchema(const YAML::Node& root);

/// checkSceneSchema on a scene file; throws LoadError when it is not
/// readable YAML.
std::vector<SchemaProblem> checkSceneFileSchema(const std::string& path);

/// "file:line:column: key: what".
std::string formatProblem(const std::string& file, const SchemaProblem& p);

/// The key reference as a Markdown table (config/scenes/README.md).
std::string sceneSchemaMarkdown();

}  // namespace evsim
