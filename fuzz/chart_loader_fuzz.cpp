// libFuzzer target: rFSM chart files. Any Lua text given to the chart loader must end
// in a chart or in a clear error, never a crash; a loaded chart is then stepped with events drawn
// from its own event names (and unknown ones) while its clock advances, so entry, exit, doo,
// guard, effect and time events all run, failing Lua callbacks included. The Lua state is
// sandboxed (no os, io, files or modules), bounded (a 4 MiB pool) and under a CPU-time budget
// (LuaState::setBudget, the Supervisor's mechanism), so hostile or looping input only costs time.
// Property beyond "no crash": after every step the Lua stack is where it was (a callback's error
// never leaves a value behind or pops one too many), and the machine's active leaf is a state of
// the chart. `./do fuzz` starts from the test charts of script/test/charts.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <lua.hpp>

#include "cobra/script/rfsm.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace std::chrono_literals;

/// A small deterministic generator seeded from the input (its FNV-1a hash).
struct Draw {
  std::uint64_t state;
  explicit Draw(std::string_view input) : state(1469598103934665603ull) {
    for (unsigned char c : input) state = (state ^ c) * 1099511628211ull;
  }
  std::uint64_t next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return state >> 33;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string code(reinterpret_cast<const char*>(data), size);
  try {
    cobra::script::LuaState lua({4 << 20, "chart fuzzer", "inputs are bounded"});
    cobra::script::installRfsm(lua);
    lua.run("os, io, dofile, loadfile, require, package, collectgarbage = nil, nil, nil, nil, nil, nil, nil\n"
            "debug = { getinfo = debug.getinfo }",
            "=sandbox");
    lua.setBudget(200ms, "fuzz input");
    lua.startStep();
    const auto chart = cobra::script::RfsmChart::loadString(lua, code, "=fuzz");
    lua.setBudget(20ms, "fuzz input");
    std::chrono::nanoseconds now{0};
    cobra::statechart::Machine machine(chart->chart(), [&now] { return now; });
    chart->bind(&machine);
    const int top = lua_gettop(lua.get());
    const auto& names = chart->chart().eventNames();
    const auto stepped = [&] {
      lua.startStep();
      machine.run(100);
      if (lua_gettop(lua.get()) != top) cobra::fuzz::fail("a step left the Lua stack changed", std::to_string(top));
      const std::string_view leaf = machine.activeLeaf();
      if (!leaf.empty()) {
        bool known = false;
        for (const auto& node : chart->chart().nodes()) known = known || node.fqn == leaf;
        if (!known) cobra::fuzz::fail("the active leaf is no state of the chart", leaf);
      }
    };
    stepped();
    Draw draw(code);
    for (int i = 0; i < 24; ++i) {
      const std::uint64_t pick = draw.next();
      if (pick % 4 == 0) {
        now += std::chrono::milliseconds(pick % 3000);  // time events come due
      } else if (!names.empty() && pick % 4 != 3) {
        (void)machine.raise(names[(pick >> 2) % names.size()]);
      } else {
        (void)machine.raise("e_unknown_to_the_chart");
      }
      stepped();
    }
  } catch (const std::exception&) {
    // a clear error is a fine outcome
  }
  return 0;
}
