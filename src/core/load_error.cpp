#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

std::string format(const std::string& file, int line, const std::string& field,
                   const std::string& message) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  std::string what = where + ": ";
  if (!field.empty()) what += "field '" + field + "': ";
  return what + message;
}

}  // namespace

LoadError::LoadError(const std::string& file, int line, const std::string& field,
                     const std::string& message)
    : std::runtime_error(format(file, line, field, message)),
      file_(file),
      line_(line),
      field_(field) {}

}  // namespace evsim
