#pragma once
// Finds the line of a table entry in the source text of a deployment file (internal).
// Lua keeps no line numbers for table entries, so they are searched: see lua_deployer.hpp.

#include <string>
#include <vector>

namespace cobra::deploy::detail {

class SourceLines {
 public:
  /// Reads `path`; an unreadable file gives no lines (every search then fails).
  explicit SourceLines(const std::string& path);
  explicit SourceLines(std::vector<std::string> lines) : lines_(std::move(lines)) {}

  /// The 1-based line where the list passed in the call on `call_line` is defined: for
  /// `startComponents(start_list)` the line of `start_list = {` (searched backwards from the
  /// call, then forwards), for an inline table `startComponents({` the call line itself.
  /// 0 when not found.
  int listStart(int call_line) const;
  /// The first line at or after `from` containing every one of `needles`; 0 when none.
  int find(int from, const std::vector<std::string>& needles) const;

 private:
  std::vector<std::string> lines_;
};

}  // namespace cobra::deploy::detail
