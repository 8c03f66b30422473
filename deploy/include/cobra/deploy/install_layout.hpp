#pragma once
/// @file
/// Where an installed cobra keeps what it reads at run time, found from the running executable
/// so that an installation can be moved as a whole (relocatable): with the tool in
/// `<prefix>/bin`, its data is in `<prefix>/share/cobra` and its packages in
/// `<prefix>/lib/cobra/packages` (the CMake install layout, GNUInstallDirs).

#include <filesystem>

namespace cobra::deploy {

/// The running program's file (/proc/self/exe), or an empty path when it cannot be read.
std::filesystem::path runningExecutable();

/// cobra's run-time data folder (holds `charts/`, the reusable supervisor charts): the
/// environment variable COBRA_DATA_DIR when set, else `<folder of executable>/../share/cobra`
/// when it exists (the installed tool; cobra's build tree mirrors it for its tool), else an
/// empty path.
std::filesystem::path dataDirectory(const std::filesystem::path& executable = runningExecutable());

/// The folder of installed shared-library packages, `<folder of executable>/../lib/cobra/packages`,
/// or an empty path when it does not exist.
std::filesystem::path installedPackageDirectory(const std::filesystem::path& executable = runningExecutable());

}  // namespace cobra::deploy
