#include "cobra/deploy/install_layout.hpp"

#include <cstdlib>
#include <system_error>

// Relative paths from the installed tool's folder, set by CMake from GNUInstallDirs.
#ifndef COBRA_DATA_DIR_FROM_BIN
#define COBRA_DATA_DIR_FROM_BIN "../share/cobra"
#endif
#ifndef COBRA_PACKAGE_DIR_FROM_BIN
#define COBRA_PACKAGE_DIR_FROM_BIN "../lib/cobra/packages"
#endif

namespace cobra::deploy {
namespace {

/// `<folder of the running executable>/relative` when that folder exists, else empty.
std::filesystem::path besideExecutable(const char* relative) {
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return {};
  const auto folder = (executable.parent_path() / relative).lexically_normal();
  return std::filesystem::is_directory(folder, error) ? folder : std::filesystem::path{};
}

}  // namespace

std::filesystem::path dataDirectory() {
  if (const char* from_environment = std::getenv("COBRA_DATA_DIR"); from_environment && *from_environment)
    return from_environment;
  return besideExecutable(COBRA_DATA_DIR_FROM_BIN);
}

std::filesystem::path installedPackageDirectory() { return besideExecutable(COBRA_PACKAGE_DIR_FROM_BIN); }

}  // namespace cobra::deploy
