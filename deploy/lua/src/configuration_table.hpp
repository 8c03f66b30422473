#pragma once
// Reads a Lua table { Component = { property = value } } as a configuration (internal): shared by
// configuration files (lua_configuration.hpp) and defineConfiguration of deployment files.

#include <string>

#include "cobra/deploy/deployment_set.hpp"
#include "source_lines.hpp"

struct lua_State;

namespace cobra::deploy::detail {

/// The configuration `name` held by the table at stack index `table`: components and properties
/// in name order, values in the property types' text form (numbers, booleans, strings, arrays of
/// numbers as "[a, b]"). Each value's location is the line of its `property =` in `lines` at or
/// after `where` (else `where`). Calls only Lua functions that cannot raise.
/// @throws core::Error "file:line: ..." on a key that is not a name or a value without a text form.
ConfigurationSpec configurationFromTable(lua_State* L, int table, const std::string& name, const SourceLocation& where,
                                         const SourceLines& lines);

}  // namespace cobra::deploy::detail
