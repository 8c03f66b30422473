#pragma once
// Reads the entry file's `placement` table (placement.hpp) for the Lua deployer (internal).

#include <string>

#include <lua.hpp>

#include "cobra/deploy/placement.hpp"

namespace cobra::deploy::detail {

/// The placement table at `index`; its entries' lines are searched in `entry_file` (the file
/// that declares it). @throws core::Error "file:line: placement ..." for a malformed table.
PlacementSpec readPlacement(lua_State* L, int index, const std::string& entry_file);

}  // namespace cobra::deploy::detail
