// Output paths of evsim, checked before a run (evsim/output_paths.h).
#include "output_paths.h"

#include <filesystem>
#include <fstream>
#include <system_error>

namespace evsim {

namespace fs = std::filesystem;

std::string checkWritableFile(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return path + " is a folder, not a file";
  const bool existed = fs::exists(path, ec);
  {
    std::ofstream probe(path, std::ios::app);
    if (!probe) return "cannot write " + path;
  }
  if (!existed) fs::remove(path, ec);
  return "";
}

std::string prepareOutputFolder(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !fs::is_directory(path, ec)) return "cannot create the folder " + path;
  const std::string probe = (fs::path(path) / ".evsim_write_test").string();
  const std::string why = checkWritableFile(probe);
  return why.empty() ? "" : "cannot write into the folder " + path;
}

}  // namespace evsim
