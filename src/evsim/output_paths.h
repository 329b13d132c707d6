// Output files and folders checked before a run starts, so that a bad path
// fails at once, not after the whole run.
#pragma once

#include <string>

namespace evsim {

/// "" when a file can be written at `path` (created and removed again if it
/// did not exist), else why not.
std::string checkWritableFile(const std::string& path);

/// "" when `path` is (or could be created as) a writable folder, else why not.
std::string prepareOutputFolder(const std::string& path);

}  // namespace evsim
