#pragma once
// `cobra faults matrix` (the fault matrix: test/fault_matrix/README.md) and `cobra soak` (random runs
// of it in one process for a given time, with memory and descriptors over time).

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace cobra::tools {

class FaultsCommands {
 public:
  /// Adds `faults matrix` and `soak` to `app`.
  explicit FaultsCommands(CLI::App& app);
  /// True when one of them was given.
  bool chosen() const;
  /// Runs the one given. Exit status: 0 every cell as the table expects (the soak: it ran and its
  /// descriptors stayed constant), 1 otherwise; a bad table throws (cobra: FILE:LINE: ...).
  int run() const;

 private:
  int runMatrix() const;
  int runSoak() const;

  CLI::App* matrix_ = nullptr;
  CLI::App* soak_ = nullptr;
  std::string table_ = "test/fault_matrix/matrix.lua", root_ = ".";
  std::vector<std::string> tasks_, only_;
  int jobs_ = 2;
  double cell_time_ = 600.0;
  std::string doc_, check_doc_;
  double duration_ = 60.0;
  unsigned long long seed_ = 1;
  std::string report_;
};

}  // namespace cobra::tools
