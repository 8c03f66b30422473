#pragma once
// A task chart's peers as fakes, for the chart tests of the applications (needs cobra::script and
// cobra::statechart; not part of any library): every operation called on a peer and every event
// emitted or raised is appended to the Lua table `log` as "Peer:operation", "emit:event" or
// "raise:event"; the Lua function `drain()` returns them one per line and clears them. An
// EntryLogger puts the states entered into the same log ("enter:FQN"), so that the order of calls
// and entries is kept.

#include <initializer_list>
#include <string>
#include <string_view>

#include "cobra/script/lua_state.hpp"
#include "cobra/statechart/machine.hpp"

namespace cobra::test_support {

/// The Lua chunk that defines `log`, `emit`, `raise`, `drain` and a fake global per name of `peers`.
inline std::string fakePeersLua(std::initializer_list<std::string_view> peers) {
  std::string names;
  for (const std::string_view peer : peers)
    names += std::string(names.empty() ? "" : ", ") + "\"" + std::string(peer) + "\"";
  return R"(
log = {}
function emit(name) log[#log + 1] = "emit:" .. name end
function raise(name) log[#log + 1] = "raise:" .. name end
local function fake(peer)
  return setmetatable({}, { __index = function(_, op) return function() log[#log + 1] = peer .. ":" .. op end end })
end
for _, p in ipairs({ )" + names + R"( }) do _G[p] = fake(p) end
function drain() local text = table.concat(log, "\n") log = {} return text end
)";
}

/// Appends "enter:FQN" to the Lua `log` of `lua` for every state the observed machine enters.
struct EntryLogger : statechart::Observer {
  script::LuaState* lua = nullptr;
  void entered(std::string_view fqn) override { lua->run("log[#log + 1] = 'enter:" + std::string(fqn) + "'"); }
};

}  // namespace cobra::test_support
