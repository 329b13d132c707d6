// Typed access to YAML nodes with errors (LoadError) that name the file, the
// line and the field. Shared by the loaders of YAML files.
#pragma once

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "endovascular_sim/core/types.h"

namespace evsim {

class YamlReader {
 public:
  explicit YamlReader(std::string file) : file_(std::move(file)) {}
  /// Reads `text` in place of the file's contents (errors still name `file`).
  YamlReader(std::string file, std::string text)
      : file_(std::move(file)), text_(std::move(text)), from_text_(true) {}

  /// Parses the file, or the text (throws LoadError when it cannot be read
  /// or is not YAML).
  YAML::Node load() const;

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& what) const;

  YAML::Node required(const YAML::Node& parent, const std::string& key,
                      const std::string& field) const;

  /// A finite number.
  double number(const YAML::Node& n, const std::string& field) const;
  /// parent[key] as a finite number, or fallback when absent; the field is
  /// named prefix + key.
  double number(const YAML::Node& parent, const std::string& key, const std::string& prefix,
                double fallback) const;
  /// A whole number.
  int integer(const YAML::Node& n, const std::string& field) const;
  std::string text(const YAML::Node& n, const std::string& field) const;
  /// Checks that n is a map whose keys are all in `allowed`, each once: an
  /// unknown key is refused with the nearest allowed one ("did you mean")
  /// and the list, a repeated key as a duplicate (yaml-cpp would keep the
  /// first silently). `field` names the map ("" the file's top level).
  void keys(const YAML::Node& n, const std::string& field,
            std::initializer_list<const char*> allowed) const;
  void keys(const YAML::Node& n, const std::string& field,
            const std::vector<std::string>& allowed) const;
  Vec3 vector3(const YAML::Node& n, const std::string& field) const;

  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::string text_;
  bool from_text_{false};
};

}  // namespace evsim
