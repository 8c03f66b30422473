#include "cobra/run/run_spec.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <lua.hpp>

#include "cobra/deploy/suggest.hpp"
#include "cobra/run/observer.hpp"
#include "lua_reader.hpp"

namespace cobra::run {
namespace {
using detail::Reader;
using detail::linesOf;
using detail::split;
using detail::chartState;

Trigger readTrigger(const Reader& entry) {
  Trigger t;
  const bool found = entry.table("on", [&](const Reader& on) {
    const int kinds = on.has("event") + on.has("state") + on.has("time");
    if (kinds != 1) on.fail("give exactly one of event = \"NAME\", state = \"chart:path\", time = s");
    if (on.has("event")) {
      t.kind = Trigger::Kind::Event;
      t.event = on.string("event", true);
      t.source = on.string("source", false);
    } else if (on.has("state")) {
      t.kind = Trigger::Kind::State;
      std::tie(t.chart, t.state) = chartState(on, on.string("state", true));
    } else {
      t.kind = Trigger::Kind::Time;
      t.time = on.number("time", 0.0);
    }
  });
  if (!found) entry.fail("needs `on = { event = ... | state = ... | time = ... }`");
  return t;
}

// One action or fault entry; its table is kept in the registry for the runner to play.
ActionSpec readAction(Reader& entry, bool repeat_default) {
  ActionSpec a;
  a.on = readTrigger(entry);
  a.after = entry.number("after", 0.0);
  if (a.after < 0.0) entry.fail("`after` must be >= 0 s");
  a.repeat = entry.boolean("repeat", repeat_default);
  a.every = entry.number("every", 0.0);
  if (!(a.every >= 0.0)) entry.fail("`every` must be >= 0 s (0: once per trigger)");
  a.chance = entry.number("chance", 1.0);
  if (!(a.chance >= 0.0 && a.chance <= 1.0)) entry.fail("`chance` must be a probability, 0 to 1");
  if (a.chance < 1.0 && a.every <= 0.0) entry.fail("`chance` needs `every` (s): each period's play happens with that probability");
  const double seed = entry.number("seed", 1.0);
  if (!(seed >= 0.0 && seed <= 4294967295.0) || seed != std::floor(seed)) entry.fail("`seed` must be an integer, 0 to 2^32 - 1");
  a.seed = static_cast<unsigned>(seed);
  const int kinds = entry.has("call") + entry.has("write") + entry.has("set") + entry.has("lua") + entry.has("throw");
  if (kinds != 1) entry.fail("give exactly one of call = \"Comp.operation\", write = { port = , value = }, "
                             "set = { property = , value = }, lua = \"deployer code\", throw = \"Comp\"");
  if (entry.has("throw")) {
    // The component's next updateHook throws (core/fault_injection.hpp): it goes to Exception.
    a.kind = ActionSpec::Kind::Throw;
    a.component = entry.string("throw", true);
    entry.setLine(entry.lineOf(a.component));
    a.text = "throw in " + a.component + ".updateHook";
  } else if (entry.has("call")) {
    a.kind = ActionSpec::Kind::Call;
    const std::string target = entry.string("call", true);
    entry.setLine(entry.lineOf(target));
    std::tie(a.component, a.member) = split(entry, target, "operation");
    a.text = "call " + target;
  } else if (entry.has("lua")) {
    a.kind = ActionSpec::Kind::Lua;
    a.text = "lua: " + entry.string("lua", true);
  } else {
    const bool write = entry.has("write");
    a.kind = write ? ActionSpec::Kind::Write : ActionSpec::Kind::Set;
    entry.table(write ? "write" : "set", [&](const Reader& what) {
      const std::string target = what.string(write ? "port" : "property", true);
      entry.setLine(entry.lineOf(target));
      std::tie(a.component, a.member) = split(what, target, write ? "port" : "property");
      if (!what.has("value")) what.fail("needs `value`");
      a.text = std::string(write ? "write " : "set ") + target;
    });
  }
  a.where = entry.where();
  lua_pushvalue(entry.state(), -1);
  a.lua_ref = luaL_ref(entry.state(), LUA_REGISTRYINDEX);
  return a;
}

// The identifying string of an action entry, for its line.
void placeAction(Reader& entry) {
  for (const char* key : {"call", "lua", "throw"})
    if (entry.has(key)) entry.setLine(entry.lineOf(entry.string(key, false)));
}

// The runner's own fields of the `run` table; every other key is a section of an observer.
constexpr const char* kRunnerFields[] = {"title", "charts", "fold", "failures", "explain", "safe_stop_reason",
                                         "safe_stop_linger", "stall_notice", "step", "actions"};

// Every section of `run` other than the runner's own, made into its observer in the registry's
// order; a key no observer is registered for is refused, naming the known sections.
void readObserverSections(const Reader& run, RunSpec& spec) {
  lua_State* L = run.state();
  const std::vector<ObserverRegistry::Kind> kinds = ObserverRegistry::kinds();
  std::vector<std::string> keys = run.keys();
  std::sort(keys.begin(), keys.end(), [&](const std::string& a, const std::string& b) {
    return run.lineOfKey(a) < run.lineOfKey(b);
  });
  for (const std::string& key : keys) {
    if (std::find(std::begin(kRunnerFields), std::end(kRunnerFields), key) != std::end(kRunnerFields)) continue;
    if (std::any_of(kinds.begin(), kinds.end(), [&](const auto& k) { return k.name == key; })) continue;
    std::vector<std::string> known(std::begin(kRunnerFields), std::end(kRunnerFields));
    for (const auto& k : kinds) known.push_back(k.name);
    throw std::runtime_error(Where{run.where().file, run.lineOfKey(key)}.text() + ": run." + key + ": unknown section '" +
                             key + "' (no observer of this name is registered: a package adds one with "
                             "ObserverRegistry::add)" + deploy::suggestionText(key, known, "sections"));
  }
  for (const ObserverRegistry::Kind& kind : kinds) {
    lua_getfield(L, -1, kind.name.c_str());
    if (lua_isnil(L, -1)) {
      lua_pop(L, 1);
      continue;
    }
    // cobra's own sections find their entries' lines from the run table's (as they always did);
    // a package's section from its own key's line.
    const int line = kind.owner == "cobra" ? run.line() : run.lineOfKey(kind.name);
    Reader reader(L, run.file(), run.lines(), "run." + kind.name, line);
    std::unique_ptr<Observer> observer = kind.make(Section(reader, spec));
    lua_pop(L, 1);
    if (observer) spec.observers.push_back({kind.name, {run.file(), run.lineOfKey(kind.name)}, std::move(observer)});
  }
}

}  // namespace

std::string Trigger::text() const {
  switch (kind) {
    case Kind::Event: return "event " + event + (source.empty() ? "" : " from " + source);
    case Kind::State: return "state " + chart + ":" + state;
    case Kind::Time: break;
  }
  char text[48];
  std::snprintf(text, sizeof text, "time %.3f s", time);
  return text;
}

RunSpec readRunSpec(lua_State* L, const std::string& file) {
  RunSpec spec;
  std::vector<std::string> lines = linesOf(file);
  int run_line = 1;
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind("run = {", 0) == 0 || lines[i].rfind("run={", 0) == 0) run_line = static_cast<int>(i + 1);
  lua_getglobal(L, "run");
  Reader run(L, file, lines, "run", run_line);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    throw std::runtime_error(file + ": no `run = { charts = { ... } }` table: the runner needs to know which task "
                             "charts end the run (run/README.md)");
  }
  if (!lua_istable(L, -1)) run.fail("must be a table");
  spec.title = run.string("title", false, "Run of " + file);
  spec.step = run.number("step", spec.step, true);
  spec.fold = run.strings("fold");
  spec.failures = run.strings("failures");
  spec.safe_stop_reason = run.string("safe_stop_reason", false);
  spec.safe_stop_linger = run.number("safe_stop_linger", spec.safe_stop_linger);
  spec.stall_notice = run.number("stall_notice", spec.stall_notice);
  run.table("explain", [&](const Reader& explain) {
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
      if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING)
        explain.fail("entries must be event = \"operation\"");
      spec.explain[lua_tostring(L, -2)] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
  });
  run.list("charts", [&](Reader& c) {
    ChartSpec chart;
    chart.name = c.string("name", true);
    chart.supervisor = c.string("supervisor", true);
    chart.done = c.string("done", true);
    chart.safe_stop = c.string("safe_stop", false);
    chart.scope = c.string("scope", false);
    chart.sources = c.strings("sources");
    chart.where = c.where();
    for (const ChartSpec& other : spec.charts)
      if (other.name == chart.name) c.fail("a second chart called '" + chart.name + "'");
    spec.charts.push_back(std::move(chart));
  });
  if (spec.charts.empty()) run.fail("needs `charts = { { name = , supervisor = , done = } }`: the charts that end the run");
  run.list(
      "actions",
      [&](Reader& entry) {
        placeAction(entry);
        spec.actions.push_back(readAction(entry, true));
      },
      nullptr);
  readObserverSections(run, spec);
  lua_pop(L, 1);
  return spec;
}

std::vector<ActionSpec> readFaults(lua_State* L, const std::string& file) {
  if (luaL_loadfile(L, file.c_str()) != LUA_OK || lua_pcall(L, 0, 1, 0) != LUA_OK) {
    std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(no message)";
    lua_pop(L, 1);
    throw std::runtime_error(message);
  }
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    throw std::runtime_error(file + ": a faults file returns a list: return { { on = { ... }, call = ... }, ... }");
  }
  std::vector<ActionSpec> out;
  const std::vector<std::string> lines = linesOf(file);
  std::vector<int> starts;  // entry i starts on the line of the i-th `on = {`
  for (std::size_t l = 0; l < lines.size(); ++l)
    if (lines[l].find("on = {") != std::string::npos || lines[l].find("on={") != std::string::npos)
      starts.push_back(static_cast<int>(l + 1));
  const lua_Integer n = luaL_len(L, -1);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    const int line = static_cast<std::size_t>(i) <= starts.size() ? starts[static_cast<std::size_t>(i - 1)] : 1;
    Reader entry(L, file, lines, "fault " + std::to_string(i), line);
    if (!lua_istable(L, -1)) entry.fail("must be a table { on = { ... }, call/write/set/lua = ... }");
    placeAction(entry);
    out.push_back(readAction(entry, false));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return out;
}

}  // namespace cobra::run
