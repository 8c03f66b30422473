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

/// `<folder of executable>/relative` when that folder exists, else empty.
std::filesystem::path besideExecutable(const std::filesystem::path& executable, const char* relative) {
  if (executable.empty()) return {};
  const auto folder = (executable.parent_path() / relative).lexically_normal();
  std::error_code error;
  return std::filesystem::is_directory(folder, error) ? folder : std::filesystem::path{};
}

}  // namespace

std::filesystem::path runningExecutable() {
  std::error_code error;
  auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path{} : executable;
}

std::filesystem::path dataDirectory(const std::filesystem::path& executable) {
  if (const char* from_environment = std::getenv("COBRA_DATA_DIR"); from_environment && *from_environment)
    return from_environment;
  return besideExecutable(executable, COBRA_DATA_DIR_FROM_BIN);
}

std::filesystem::path installedPackageDirectory(const std::filesystem::path& executable) {
  return besideExecutable(executable, COBRA_PACKAGE_DIR_FROM_BIN);
}

}  // namespace cobra::deploy
