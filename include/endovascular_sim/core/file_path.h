// Small helpers on file paths shared by the loaders and `evsim check`.
#pragma once

#include <string>

namespace evsim {

/// The path's extension, lower case, with its dot (".vtp"; "" when none):
/// what a loader is chosen by.
std::string lowerCaseExtension(const std::string& path);

}  // namespace evsim
