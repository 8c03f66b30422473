#pragma once
/// @file
/// Configuration files as Lua tables (ARCHITECTURE §6): `slow.lua` in the configuration folder is the
/// configuration "slow", and returns property values per component:
/// @code
/// return {
///   Sine = { frequency = 2.0, amplitude = 0.5 },   -- Hz, 1
///   Gain = { k = 3 },
///   Planner = { joint_limits = { -1.5, 1.5 } },    -- arrays become "[a, b]"
/// }
/// @endcode
/// Values are turned into the property types' text form (numbers, true/false, strings, arrays of
/// numbers), and checked when the configuration is applied, every value at once.

#include <filesystem>
#include <vector>

#include "cobra/deploy/deployment_set.hpp"

struct lua_State;

namespace cobra::deploy {

/// The property text form of the Lua value at `index` (a number, true/false, a string, an array
/// of numbers as "[a, b]"): what a configuration file's value becomes, for
/// PropertyBase::checkText. False when the value has none. Calls only Lua functions that cannot
/// raise.
bool luaValueText(lua_State* L, int index, std::string& out);

/// Reads one Lua configuration file; each value's location is the line of its `name =`.
/// @throws core::Error "file:line: ..." when the file does not run, does not return a table of
/// tables, or holds a value that has no text form (a function, a nested non-array table).
ConfigurationSpec loadLuaConfigurationFile(const std::filesystem::path& file);

/// Every `*.lua` file of `folder`, in name order (none when the folder has none).
std::vector<ConfigurationSpec> loadLuaConfigurationFolder(const std::filesystem::path& folder);

}  // namespace cobra::deploy
