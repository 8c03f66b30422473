#include "fsm_command.hpp"

#include <cstdio>
#include <sstream>

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
