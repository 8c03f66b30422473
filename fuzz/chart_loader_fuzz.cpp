// libFuzzer target: rFSM chart files (issue 4). Any Lua text given to the chart loader must end
// in a chart or in a clear error, never a crash; a loaded chart is then stepped with a few events.
// The Lua state is sandboxed (no os, io, files or modules), bounded (a 4 MiB pool) and stopped
// after a million instructions, so hostile or looping input only costs time. `./do fuzz` starts
// from the test charts of script/test/charts.

#include <cstddef>
#include <cstdint>
#include <string>

#include <lua.hpp>

#include "cobra/script/rfsm.hpp"

namespace {

void stopRunaways(lua_State* L, lua_Debug*) { luaL_error(L, "instruction budget exhausted"); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string code(reinterpret_cast<const char*>(data), size);
  try {
    cobra::script::LuaState lua({4 << 20, "chart fuzzer", "inputs are bounded"});
    cobra::script::installRfsm(lua);
    lua.run("os, io, dofile, loadfile, require, package, collectgarbage = nil, nil, nil, nil, nil, nil, nil\n"
            "debug = { getinfo = debug.getinfo }",
            "=sandbox");
    lua_sethook(lua.get(), stopRunaways, LUA_MASKCOUNT, 1000000);
    const auto chart = cobra::script::RfsmChart::loadString(lua, code, "=fuzz");
    cobra::statechart::Machine machine(chart->chart(), {});
    chart->bind(&machine);
    machine.run(100);
    for (const char* event : {"e_start", "e_done", "e_x", "e_stop"}) {
      (void)machine.raise(event);
      machine.run(100);
    }
  } catch (const std::exception&) {
    // a clear error is a fine outcome
  }
  return 0;
}
