#pragma once
// The codecs of cobra's types defined outside core (internal to cobra::types): TGL.MultiAxisPath,
// the Motion Planner's planned path (components/motion/path_type.hpp).

#include <string_view>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/script/lua_codec.hpp"

namespace cobra::script {

/// An array of waypoints, each an array of axis values: {{0, 0.1}, {0.2, 0.3}}.
template <>
struct LuaCodec<trajectory::MultiAxisPath> {
  static std::string_view form();
  static void read(lua_State* L, int index, trajectory::MultiAxisPath& out);
  static void push(lua_State* L, const trajectory::MultiAxisPath& value);
};

}  // namespace cobra::script

namespace cobra::components {

/// A path has no fixed number of values: one text column (its text form).
template <>
struct CsvCodec<trajectory::MultiAxisPath> : TextCsvCodec<trajectory::MultiAxisPath> {};

}  // namespace cobra::components
