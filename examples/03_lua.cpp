// Example 03: Lua. A LuaComponent whose hooks live in 03_lua.lua, and a Lua console-like state
// that reaches every component by name, as the thesis' Configurator getReferences() does:
// `Sine.frequency = 5`, `Rect.k`, `Rect:getState()`.

#include <cstdio>

#include "cobra/components/signal/recorder.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/core/core.hpp"
#include "cobra/script/bindings.hpp"
#include "cobra/script/lua_component.hpp"
#include "cobra/script/lua_state.hpp"

using namespace cobra;
using namespace std::chrono_literals;

int main() {
  core::ComponentRegistry registry;
  auto& sine = registry.make<components::SineGenerator>("Sine");
  auto& rect = registry.make<script::LuaComponent>("Rect", core::Role::Calculation, "|u| scaled by k, in Lua");
  auto& rec = registry.make<components::Recorder>("Rec");
  rect.setProperty("script_path", std::string(COBRA_EXAMPLES_DIR) + "/03_lua.lua");
  rect.loadScript();  // declares the script's ports, so they can be connected before configure

  core::connectPorts(sine.port("out"), rect.port("u"));
  core::connectPorts(rect.port("y"), rec.port("in"), core::ConnPolicy::buffer(8));
  core::LockstepClock clock;
  clock.add(sine, 1ms);
  clock.add(rect, 0ns);
  clock.add(rec, 0ns);

  // Everything below is plain Lua, as typed in a console or written in a deployment script.
  script::LuaState lua;
  script::getReferences(lua, registry);
  lua.run(R"(
    Sine.frequency = 100        -- Hz
    Rect.k = 2
    for _, c in ipairs({Sine, Rect, Rec}) do assert(c:configure()); assert(c:start()) end
    print("  [lua] Rect is " .. Rect:getState() .. ", k = " .. Rect.k)
  )", "=example");

  clock.advance(10ms);
  std::printf("|2 sin(2 pi 100 t)| sampled at 1 kHz:");
  for (const auto& s : rec.samples()) std::printf(" %.3f", s.value);
  std::printf("\n");

  try {
    lua.run("Rect.k = -1", "=example");
  } catch (const core::Error& e) {
    std::printf("bad input is refused: %s\n", e.what());
  }
  return rec.samples().size() == 10 ? 0 : 1;
}
