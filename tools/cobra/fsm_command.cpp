#include "fsm_command.hpp"

#include <lua.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "cobra/deploy/install_layout.hpp"
#include "cobra/script/rfsm.hpp"

namespace cobra::tools {
namespace {

/// Lua's print goes to stderr, so that stdout carries only the state paths.
constexpr const char* kPrintToStderr = R"(print = function(...)
  local parts = {}
  for i = 1, select('#', ...) do parts[i] = tostring((select(i, ...))) end
  io.stderr:write(table.concat(parts, '\t'), '\n')
end)";

/// Keeps the first failing callback: the run stops there, as a Supervisor goes to Exception.
class FailureObserver : public statechart::Observer {
 public:
  void callbackFailed(std::string_view callback, std::string_view element, std::string_view what) override {
    if (!failure.empty()) return;
    failure = std::string(callback) + " of " + std::string(element) + " failed: " + std::string(what);
  }
  std::string failure;
};

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\\\"") : std::string(1, c);
  return out + "\"";
}

std::string nodeId(int index) { return "n" + std::to_string(index); }

// CPU time a chart may take to load, and for the steps after each event, before it is cut.
constexpr std::chrono::seconds kFsmLoadBudget{10};
constexpr std::chrono::seconds kFsmStepBudget{1};

}  // namespace

int runFsm(const std::string& file, const std::string& events) {
  script::LuaState lua;
  lua.setBudget(kFsmLoadBudget, "cobra fsm run allows that much to load a chart");
  lua.startStep();
  lua.run(kPrintToStderr, "=cobra fsm");
  const auto chart = script::RfsmChart::loadFile(lua, file);
  lua.setBudget(kFsmStepBudget, "cobra fsm run allows that much per event");
  statechart::Machine machine(chart->chart(), [] { return std::chrono::steady_clock::now().time_since_epoch(); });
  FailureObserver observer;
  machine.setObserver(&observer);
  chart->bind(&machine);
  // Steps until idle; false (with the failure on stderr) when a callback failed.
  auto report = [&] {
    lua.startStep();
    for (int i = 0; i < 10000 && observer.failure.empty(); ++i) {
      const statechart::StepResult r = machine.step();
      if (r == statechart::StepResult::Idle || r == statechart::StepResult::CannotEnter) break;
    }
    std::printf("%s\n", std::string(machine.activeLeaf()).c_str());
    if (observer.failure.empty()) return true;
    std::fflush(stdout);
    std::fprintf(stderr, "cobra fsm: %s\n", observer.failure.c_str());
    return false;
  };
  if (!report()) return 1;
  std::istringstream tokens(events);
  for (std::string token; tokens >> token;) {
    if (token != "-" && machine.raise(token) != statechart::RaiseStatus::Queued)
      std::fprintf(stderr, "event '%s' not sent (queue full or name too long)\n", token.c_str());
    if (!report()) return 1;
  }
  return 0;
}

namespace {

/// A task chart's world as stand-ins (runFsmUntil): its Supervisor's functions and its peers. Every
/// line goes to stdout as "  T s  what", T the simulated time (the global cobra_fsm_now).
constexpr const char* kTaskWorld = R"lua(
local function say(what) io.stdout:write(string.format('%9.3f s  %s\n', cobra_fsm_now, what)) end
function emit(name) say('emit ' .. tostring(name)) end
function applyDeployment(name) say('applyDeployment ' .. tostring(name)) return true end
function applyConfiguration(name) say('applyConfiguration ' .. tostring(name)) return true end
-- A peer (a global named as a component: a capital first letter) answers every operation with
-- nil after saying the call; the events its answer would send are the --events you give.
local peers = {}
local function peer(name)
  if peers[name] == nil then
    peers[name] = setmetatable({}, { __index = function(_, operation)
      return function(_, ...)
        local args = {}
        for i = 1, select('#', ...) do args[i] = tostring((select(i, ...))) end
        say('call ' .. name .. ':' .. operation .. '(' .. table.concat(args, ', ') .. ')')
      end
    end })
  end
  return peers[name]
end
setmetatable(_G, { __index = function(_, name)
  if type(name) == 'string' and name:match('^%u') then return peer(name) end
end })
)lua";

int raiseFromLua(lua_State* L) {
  auto& machine = *static_cast<statechart::Machine*>(lua_touserdata(L, lua_upvalueindex(1)));
  const char* name = luaL_checkstring(L, 1);
  if (machine.raise(name) != statechart::RaiseStatus::Queued)
    return luaL_error(L, "raise('%s'): the chart's event queue is full or the name too long", name);
  return 0;
}

/// "e_a@1.5 e_b" -> (1.5, e_a), (0, e_b), in time order (stable).
std::vector<std::pair<double, std::string>> timedEvents(const std::string& events) {
  std::vector<std::pair<double, std::string>> out;
  std::istringstream tokens(events);
  for (std::string token; tokens >> token;) {
    if (token == "-") continue;
    double at = 0.0;
    if (const auto sign = token.find('@'); sign != std::string::npos) {
      const std::string time = token.substr(sign + 1);
      char* end = nullptr;
      at = std::strtod(time.c_str(), &end);
      if (time.empty() || *end != '\0' || !std::isfinite(at) || at < 0.0)
        throw std::runtime_error("--events: '" + token + "': expected NAME or NAME@SECONDS (a time >= 0 s)");
      token.erase(sign);
    }
    out.emplace_back(at, token);
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

}  // namespace

int runFsmUntil(const std::string& file, double until, double step, const std::string& events) {
  if (!(until > 0.0) || !(step > 0.0) || step > until)
    throw std::runtime_error("cobra fsm run: --until " + std::to_string(until) + " and --step " + std::to_string(step) +
                             ": expected 0 < step <= until (s)");
  const auto sends = timedEvents(events);
  script::LuaState lua;
  lua.setBudget(kFsmLoadBudget, "cobra fsm run allows that much to load a chart");
  lua.startStep();
  lua_State* L = lua.get();
  lua.run(kPrintToStderr, "=cobra fsm");
  lua_pushnumber(L, 0.0);
  lua_setglobal(L, "cobra_fsm_now");
  lua.run(kTaskWorld, "=cobra fsm task world");
  // As a Supervisor runs it: helpers beside the chart, then cobra's charts (task_steps.lua).
  std::string path = std::filesystem::path(file).parent_path().string();
  path = (path.empty() ? std::string(".") : path) + "/?.lua;";
  if (const auto data = deploy::dataDirectory(); !data.empty()) path += (data / "charts").string() + "/?.lua;";
  lua_getglobal(L, "package");
  lua_pushstring(L, path.c_str());
  lua_getfield(L, -2, "path");
  lua_concat(L, 2);
  lua_setfield(L, -2, "path");
  lua_pop(L, 1);
  double now = 0.0;
  const auto chart = script::RfsmChart::loadFile(lua, file);
  lua.setBudget(kFsmStepBudget, "cobra fsm run allows that much per step");
  statechart::Machine machine(chart->chart(), [&now] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(now));
  });
  FailureObserver observer;
  machine.setObserver(&observer);
  chart->bind(&machine);
  lua_pushlightuserdata(L, &machine);
  lua_pushcclosure(L, raiseFromLua, 1);
  lua_setglobal(L, "raise");
  std::string shown;
  std::size_t next = 0;
  const long steps = std::lround(until / step);
  for (long k = 0; k <= steps; ++k) {
    now = static_cast<double>(k) * step;
    lua_pushnumber(L, now);
    lua_setglobal(L, "cobra_fsm_now");
    for (; next < sends.size() && sends[next].first <= now + 1e-9; ++next) {
      std::printf("%9.3f s  event %s\n", now, sends[next].second.c_str());
      if (machine.raise(sends[next].second) != statechart::RaiseStatus::Queued)
        std::fprintf(stderr, "event '%s' not sent (queue full or name too long)\n", sends[next].second.c_str());
    }
    lua.startStep();
    for (int i = 0; i < 10000 && observer.failure.empty(); ++i) {
      const statechart::StepResult r = machine.step();
      const std::string leaf(machine.activeLeaf());
      if (leaf != shown) {
        std::printf("%9.3f s  state %s\n", now, leaf.c_str());
        shown = leaf;
      }
      if (r == statechart::StepResult::Idle || r == statechart::StepResult::CannotEnter) break;
    }
    if (!observer.failure.empty()) {
      std::fflush(stdout);
      std::fprintf(stderr, "cobra fsm: %s\n", observer.failure.c_str());
      return 1;
    }
  }
  std::printf("%9.3f s  until reached in %s\n", now, shown.c_str());
  return 0;
}

int checkFsm(const std::string& file) {
  script::LuaState lua;
  const auto loaded = script::RfsmChart::loadFile(lua, file);
  const statechart::Chart& chart = loaded->chart();
  int states = 0, connectors = 0;
  for (const auto& n : chart.nodes()) (n.kind == statechart::NodeKind::State ? states : connectors) += 1;
  std::printf("%s: %d state(s), %d connector(s), %zu transition(s)\n", file.c_str(), states, connectors,
              chart.transitions().size());
  for (const auto& n : chart.nodes()) {
    const char* kind = n.kind == statechart::NodeKind::Connector ? "connector" : (n.composite ? "composite" : "leaf");
    std::printf("  %-10s %-40s %s%s\n", kind, n.fqn.c_str(), n.callbacks.origin.c_str(), n.callbacks.doo ? " (doo)" : "");
  }
  for (const auto& t : chart.transitions()) {
    std::string events;
    for (statechart::EventId id : t.events) events += (events.empty() ? "" : ", ") + chart.eventNames()[id];
    std::printf("  %-50s on %-30s pn %d %s\n", t.text.c_str(), events.empty() ? "(any event)" : events.c_str(), t.pn,
                t.origin.c_str());
  }
  return 0;
}

std::string chartDot(const statechart::Chart& chart, const std::string& title) {
  std::ostringstream dot;
  dot << "digraph chart {\n  compound=true; rankdir=TB; fontname=\"sans-serif\"; label=" << quoted(title)
      << "; labelloc=t;\n  node [fontname=\"sans-serif\", fontsize=11]; edge [fontname=\"sans-serif\", fontsize=9];\n";
  const auto& nodes = chart.nodes();
  // A composite is a cluster; edges to or from it attach to an invisible anchor inside it.
  std::function<void(int, int)> emit = [&](int index, int depth) {
    const std::string indent(static_cast<std::size_t>(2 * depth + 2), ' ');
    const auto& n = nodes[static_cast<std::size_t>(index)];
    if (n.kind == statechart::NodeKind::Connector) {
      dot << indent << nodeId(index) << " [shape=point, width=" << (n.name == "initial" ? "0.15" : "0.1")
          << ", xlabel=" << quoted(n.name == "initial" ? "" : n.name) << "];\n";
      return;
    }
    if (!n.composite) {
      dot << indent << nodeId(index) << " [shape=box, style=rounded, label=" << quoted(n.name + (n.callbacks.doo ? "\ndoo" : ""))
          << "];\n";
      return;
    }
    dot << indent << "subgraph cluster_" << index << " {\n" << indent << "  label=" << quoted(n.name)
        << "; style=rounded; color=\"#555555\";\n" << indent << "  " << nodeId(index) << " [shape=point, style=invis];\n";
    for (std::size_t child = 0; child < nodes.size(); ++child)
      if (nodes[child].parent == index && static_cast<int>(child) != index) emit(static_cast<int>(child), depth + 1);
    dot << indent << "}\n";
  };
  emit(0, 0);
  for (const auto& t : chart.transitions()) {
    std::string label;
    for (statechart::EventId id : t.events) label += (label.empty() ? "" : ", ") + chart.eventNames()[id];
    if (t.pn != 0) label += " [pn " + std::to_string(t.pn) + "]";
    if (t.guard) label += " [guard]";
    dot << "  " << nodeId(t.src) << " -> " << nodeId(t.tgt) << " [label=" << quoted(label);
    if (nodes[static_cast<std::size_t>(t.src)].composite) dot << ", ltail=cluster_" << t.src;
    dot << "];\n";
  }
  dot << "}\n";
  return dot.str();
}

}  // namespace cobra::tools
