// The error every loader throws: it names the file, the line (and column
// when known) and the field: "file:line:column: field: message". A loader
// that finds several problems in one file throws LoadErrors, all of them:
// its message is the first's, with how many more there are.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace evsim {

class LoadError : public std::runtime_error {
 public:
  /// line, column: 1-based, 0 when unknown; field: the offending key or element.
  LoadError(const std::string& file, int line, const std::string& field,
            const std::string& message);
  LoadError(const std::string& file, int line, int column, const std::string& field,
            const std::string& message);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& field() const { return field_; }
  const std::string& message() const { return message_; }

 protected:
  LoadError(const LoadError& first, const std::string& what);

 private:
  std::string file_;
  int line_;
  int column_;
  std::string field_;
  std::string message_;
};

/// Every problem a loader found in one file (at least two): file(), line(),
/// field() and message() are the first's; what() adds "(and N more: `evsim
/// check FILE` lists every one)".
class LoadErrors : public LoadError {
 public:
  explicit LoadErrors(std::vector<LoadError> all);
  const std::vector<LoadError>& all() const { return all_; }

 private:
  std::vector<LoadError> all_;
};

/// Throws nothing for none, the error for one, LoadErrors for several.
void throwLoadErrors(std::vector<LoadError> errors);

}  // namespace evsim
