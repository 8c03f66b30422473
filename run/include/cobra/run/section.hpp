#pragma once
/// @file
/// A section of an application's `run` table as its observer reads it (Observer plug-ins,
/// cobra/run/observer.hpp): one Lua table with its path ("run.time_in_state") and the file:line it
/// is written at. Every reading method throws std::runtime_error
/// "file:line: run.NAME: what was expected" for a missing or badly typed field.

#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "cobra/run/run_spec.hpp"

struct lua_State;

namespace cobra::run {
namespace detail {
class Reader;
}

class Section {
 public:
  Section(const detail::Reader& reader, RunSpec& spec) : reader_(reader), spec_(spec) {}

  Where where() const;
  const std::string& path() const;  ///< "run.NAME" (or "run.NAME[2]" for an entry of a list)
  /// @throws std::runtime_error "file:line: PATH: what".
  [[noreturn]] void fail(const std::string& what) const;

  bool has(const char* key) const;
  /// A string field; absent: `fallback`, or an error when `required`.
  std::string string(const char* key, bool required, const std::string& fallback = {}) const;
  /// A finite number (> 0 when `positive`); absent: `fallback`.
  double number(const char* key, double fallback, bool positive = false) const;
  bool boolean(const char* key, bool fallback) const;
  /// A string or a list of strings; absent: empty.
  std::vector<std::string> strings(const char* key) const;
  /// Calls `each` with every entry (a table) of the list under `key`, its line found from its
  /// string field `identify`.
  void list(const char* key, const std::function<void(const Section& entry)>& each, const char* identify = "name") const;
  /// @throws std::runtime_error "file:line: PATH: unknown field 'x'; did you mean 'y'? known
  ///         fields: ..." when the table has a key not in `fields`.
  void allowOnly(std::initializer_list<const char*> fields) const;

  /// The section's value on top of the Lua stack (a table, or what was written), for the rest.
  lua_State* state() const;
  /// The `run` table read so far: cobra's own observers keep their typed part in it (the studio
  /// and a run split over hosts read it).
  RunSpec& spec() const { return spec_; }
  const detail::Reader& reader() const { return reader_; }

 private:
  const detail::Reader& reader_;
  RunSpec& spec_;
};

}  // namespace cobra::run
