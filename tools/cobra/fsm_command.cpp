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

class StderrObserver : public statechart::Observer {
 public:
  void callbackFailed(std::string_view callback, std::string_view element, std::string_view what) override {
    std::fprintf(stderr, "%.*s of %.*s failed: %.*s\n", static_cast<int>(callback.size()), callback.data(),
                 static_cast<int>(element.size()), element.data(), static_cast<int>(what.size()), what.data());
  }
};

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\\\"") : std::string(1, c);
  return out + "\"";
}

std::string nodeId(int index) { return "n" + std::to_string(index); }

}  // namespace

int runFsm(const std::string& file, const std::string& events) {
  script::LuaState lua;
  lua.run(kPrintToStderr, "=cobra fsm");
  const auto chart = script::RfsmChart::loadFile(lua, file);
  statechart::Machine machine(chart->chart(), [] { return std::chrono::steady_clock::now().time_since_epoch(); });
  StderrObserver observer;
  machine.setObserver(&observer);
  chart->bind(&machine);
  auto report = [&] {
    machine.run();
    std::printf("%s\n", std::string(machine.activeLeaf()).c_str());
  };
  report();
  std::istringstream tokens(events);
  for (std::string token; tokens >> token;) {
    if (token != "-" && machine.raise(token) != statechart::RaiseStatus::Queued)
      std::fprintf(stderr, "event '%s' not sent (queue full or name too long)\n", token.c_str());
    report();
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
