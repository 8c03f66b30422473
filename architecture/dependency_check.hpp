#pragma once
// The dependency-direction check (architecture/CMakeLists.txt): which libraries link, and which
// sources include, a module they must not depend on. Pure functions over a target list and a
// source tree, so that a test can feed them a synthetic violation.

#include <filesystem>
#include <string>
#include <vector>

namespace cobra::architecture {

/// One CMake target as dependency_targets.txt lists it.
struct Target {
  std::string name;
  std::string type;    ///< STATIC_LIBRARY, INTERFACE_LIBRARY, EXECUTABLE, ...
  std::string folder;  ///< its CMakeLists.txt's folder, relative to the project ("run", "components/signal")
  std::vector<std::string> links;  ///< the targets it links directly (LINK_LIBRARIES, INTERFACE_LINK_LIBRARIES)
};

/// Which folders may not depend on which.
struct Rule {
  std::vector<std::string> checked;    ///< folders whose libraries and sources are checked ("core", "components")
  std::vector<std::string> forbidden;  ///< folders they must not depend on ("apps", "tools", "studio")
  std::vector<std::string> skipped;    ///< folder names not scanned for includes ("test": a module's tests are no library)
  bool executables = false;            ///< also check the executables (tests, tools) of checked folders, not only libraries
};

struct Violation {
  std::string message;  ///< where (target, or file:line), what it depends on, and the rule
  std::string key;      ///< for an allow-list: "TARGET -> TARGET" or "FILE -> HEADER" (no line: lines move)
};

/// Reads the lines "name<TAB>type<TAB>folder<TAB>link link ...".
std::vector<Target> readTargets(const std::filesystem::path& file);

/// Every library (every target, with `rule.executables`) in a checked folder that links a target
/// of a forbidden folder, directly or through targets of neither kind (a checked target on the
/// way is reported for itself).
std::vector<Violation> linkViolations(const std::vector<Target>& targets, const Rule& rule);

/// Every #include in a source under `root`'s checked folders that names a header of a forbidden
/// folder: relative to the including file, or by a path that only a forbidden folder's headers end with.
std::vector<Violation> includeViolations(const std::filesystem::path& root, const Rule& rule);

/// `violations` whose key is not in `allowed`; `unused` gets the entries of `allowed` no violation needed.
std::vector<Violation> notAllowed(const std::vector<Violation>& violations, const std::vector<std::string>& allowed,
                                  std::vector<std::string>& unused);

}  // namespace cobra::architecture
