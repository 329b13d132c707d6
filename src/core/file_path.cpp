// Path helpers (core/file_path.h).
#include "endovascular_sim/core/file_path.h"

#include <cctype>
#include <filesystem>

namespace evsim {

std::string lowerCaseExtension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

}  // namespace evsim
