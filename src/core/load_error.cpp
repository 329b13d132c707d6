// The error every loader throws: it names the file, the line (and column when
// known) and the field: "file:line:column: field: message". Declared and
// documented in endovascular_sim/core/load_error.h.
#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

std::string format(const std::string& file, int line, int column, const std::string& field,
                   const std::string& message) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  if (line > 0 && column > 0) where += ":" + std::to_string(column);
  return where + ": " + (field.empty() ? "" : field + ": ") + message;
}

}  // namespace

LoadError::LoadError(const std::string& file, int line, const std::string& field,
                     const std::string& message)
    : LoadError(file, line, 0, field, message) {}

LoadError::LoadError(const std::string& file, int line, int column, const std::string& field,
                     const std::string& message)
    : std::runtime_error(format(file, line, column, field, message)),
      file_(file),
      line_(line),
      column_(column),
      field_(field),
      message_(message) {}

LoadError::LoadError(const LoadError& first, const std::string& what)
    : std::runtime_error(what),
      file_(first.file_),
      line_(first.line_),
      column_(first.column_),
      field_(first.field_),
      message_(first.message_) {}

LoadErrors::LoadErrors(std::vector<LoadError> all)
    : LoadError(all.front(), std::string(all.front().what()) + " (and " +
                                 std::to_string(all.size() - 1) + " more: `evsim check " +
                                 all.front().file() + "` lists every one)"),
      all_(std::move(all)) {}

void throwLoadErrors(std::vector<LoadError> errors) {
  if (errors.empty()) return;
  if (errors.size() == 1) throw errors.front();
  throw LoadErrors(std::move(errors));
}

}  // namespace evsim
