// The error every loader throws: it names the file, the line and the field.
#pragma once

#include <stdexcept>
#include <string>

namespace evsim {

class LoadError : public std::runtime_error {
 public:
  /// line: 1-based, 0 when unknown; field: the offending key or element.
  LoadError(const std::string& file, int line, const std::string& field,
            const std::string& message);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& field() const { return field_; }

 private:
  std::string file_;
  int line_;
  std::string field_;
};

}  // namespace evsim
