#include "cobra/statechart/chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cobra::statechart {
namespace {

std::string where(const std::string& origin) { return origin.empty() ? std::string() : origin + ": "; }

/// Lua 5.4's tostring(tonumber(text)): rFSM names a time event after its timespec as Lua prints
/// it, so "e_after(1.50)" waits for the event "e_after(1.5)@<src>" and "e_after(2)" for
/// "e_after(2)@<src>" (an integer stays one, a float keeps its ".0").
std::string luaNumberText(std::string_view text, double value) {
  const bool integer = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (integer && value < 9.2e18) return std::to_string(static_cast<long long>(value));
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.14g", value);
  std::string printed(buffer);
  if (printed.find_first_of(".eni") == std::string::npos) printed += ".0";
  return printed;
}

/// "e_after(2.5)" -> 2.5 s relative, "e_at(3)" -> 3 s absolute, with the name rFSM gives the
/// event before "@<src>"; false for anything else.
bool parseTimeEvent(std::string_view name, double& seconds, bool& absolute, std::string& canonical) {
  std::string_view inside;
  std::string_view kind;
  if (name.starts_with("e_after(") && name.ends_with(")")) {
    kind = "e_after";
    absolute = false;
  } else if (name.starts_with("e_at(") && name.ends_with(")")) {
    kind = "e_at";
    absolute = true;
  } else {
    return false;
  }
  inside = name.substr(kind.size() + 1, name.size() - kind.size() - 2);
  while (!inside.empty() && inside.front() == ' ') inside.remove_prefix(1);
  while (!inside.empty() && inside.back() == ' ') inside.remove_suffix(1);
  const std::string text(inside);
  char* end = nullptr;
  seconds = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(seconds) || seconds < 0.0) return false;
  canonical = std::string(kind) + "(" + luaNumberText(inside, seconds) + ")";
  return true;
}

}  // namespace

bool StepEvents::contains(std::string_view name) const noexcept {
  return std::any_of(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.name == name; });
}

int Chart::find(std::string_view fqn) const noexcept {
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].fqn == fqn) return static_cast<int>(i);
  return -1;
}

EventId Chart::eventId(std::string_view name) const noexcept {
  const auto it = std::lower_bound(by_name_.begin(), by_name_.end(), name,
                                   [](const auto& entry, std::string_view n) { return entry.first < n; });
  return it != by_name_.end() && it->first == name ? it->second : kUnknownEvent;
}

ChartBuilder::ChartBuilder() {
  chart_.nodes_.push_back(Chart::Node{NodeKind::State, "root", "root", 0, 0, false, -1, {}, {}, kUnknownEvent});
}

void ChartBuilder::setRootCallbacks(StateSpec callbacks) { chart_.nodes_[0].callbacks = std::move(callbacks); }

std::string ChartBuilder::nodesNear(std::string_view missing_fqn) const {
  std::string_view scope = missing_fqn;
  int found = -1;
  while (found < 0 && scope.find('.') != std::string_view::npos) {
    scope = scope.substr(0, scope.rfind('.'));
    found = chart_.find(scope);
  }
  if (found < 0) return "; paths start at root, a leading dot or a name of the transition's state";
  std::string names;
  for (const Chart::Node& n : chart_.nodes_)
    if (n.parent == found && &n != &chart_.nodes_[0]) names += (names.empty() ? "" : ", ") + n.fqn;
  return names.empty() ? "; " + std::string(scope) + " has no nodes" : "; the nodes of " + std::string(scope) + " are " + names;
}

int ChartBuilder::lookup(std::string_view fqn) const {
  const int found = chart_.find(fqn);
  if (found < 0) throw std::invalid_argument("chart: no state '" + std::string(fqn) + "' to add to");
  return found;
}

int ChartBuilder::addNode(std::string_view parent_fqn, std::string name, NodeKind kind, StateSpec spec) {
  const int parent = lookup(parent_fqn);
  const std::string kind_name = kind == NodeKind::State ? "state" : "connector";
  if (name.empty() || name.find('.') != std::string::npos || name == "root")
    throw std::invalid_argument(where(spec.origin) + "chart: a " + kind_name + " in " + std::string(parent_fqn) +
                                " is named '" + name + "'; names are non-empty, without dots, and not 'root'");
  const std::string fqn = std::string(parent_fqn) + "." + name;
  if (chart_.find(fqn) >= 0)
    throw std::invalid_argument(where(spec.origin) + "chart: " + fqn + " is defined twice; give each node of " +
                                std::string(parent_fqn) + " its own name");
  if (chart_.nodes_[static_cast<std::size_t>(parent)].kind == NodeKind::Connector)
    throw std::invalid_argument(where(spec.origin) + "chart: " + fqn + ": a connector cannot contain nodes");
  if (kind == NodeKind::State && name == "initial")
    throw std::invalid_argument(where(spec.origin) + "chart: " + fqn +
                                " is a state, but 'initial' names the initial connector; rename the state");
  const int depth = chart_.nodes_[static_cast<std::size_t>(parent)].depth + 1;
  chart_.nodes_.push_back(Chart::Node{kind, std::move(name), fqn, parent, depth, false, -1, {}, std::move(spec),
                                      kUnknownEvent});
  chart_.nodes_[static_cast<std::size_t>(parent)].composite = true;
  const int index = static_cast<int>(chart_.nodes_.size() - 1);
  if (kind == NodeKind::Connector && chart_.nodes_.back().name == "initial")
    chart_.nodes_[static_cast<std::size_t>(parent)].initial = index;
  return index;
}

void ChartBuilder::addState(std::string_view parent_fqn, std::string name, StateSpec spec) {
  addNode(parent_fqn, std::move(name), NodeKind::State, std::move(spec));
}

void ChartBuilder::addConnector(std::string_view parent_fqn, std::string name, std::string origin) {
  StateSpec spec;
  spec.origin = std::move(origin);
  addNode(parent_fqn, std::move(name), NodeKind::Connector, std::move(spec));
}

void ChartBuilder::addTransition(std::string_view scope_fqn, TransitionSpec spec) {
  pending_.push_back({lookup(scope_fqn), std::move(spec)});
}

Chart ChartBuilder::build() {
  std::vector<std::string> problems;
  auto& nodes = chart_.nodes_;
  // rFSM creates the `initial` connector a transition of a composite scope leaves from.
  for (const PendingTransition& p : pending_) {
    const Chart::Node& scope = nodes[static_cast<std::size_t>(p.scope)];
    if (p.spec.src == "initial" && scope.initial < 0 && (scope.composite || p.scope == 0))
      addConnector(scope.fqn, "initial", p.spec.origin);
  }
  for (const Chart::Node& n : nodes)
    if (n.kind == NodeKind::State && n.composite && n.callbacks.doo)
      problems.push_back(where(n.callbacks.origin) + "state " + n.fqn +
                         " has a doo but is composite; doo is allowed in leaf states only");
  if (nodes[0].initial < 0)
    problems.push_back("chart: root has no initial connector; add a transition from 'initial' to the first state");

  // Resolves `path` as rFSM does: local name, ".relative" or absolute "root.a.b".
  auto resolve = [&](const std::string& path, int scope, std::string& why) -> int {
    std::string fqn;
    if (path.find('.') == std::string::npos) fqn = nodes[static_cast<std::size_t>(scope)].fqn + "." + path;
    else if (path.front() == '.') fqn = nodes[static_cast<std::size_t>(scope)].fqn + path;
    else fqn = path == "root" || path.starts_with("root.") ? path : "root." + path;
    const int found = chart_.find(fqn);
    if (found < 0) why = "no node '" + fqn + "'" + nodesNear(fqn);
    return found;
  };
  auto intern = [&](const std::string& name) -> EventId {
    if (const EventId known = chart_.eventId(name); known != kUnknownEvent) return known;
    const auto id = static_cast<EventId>(chart_.event_names_.size());
    chart_.event_names_.push_back(name);
    chart_.by_name_.insert(std::upper_bound(chart_.by_name_.begin(), chart_.by_name_.end(), name,
                                            [](const std::string& n, const auto& e) { return n < e.first; }),
                           {name, id});
    return id;
  };
  for (Chart::Node& n : nodes)
    if (n.kind == NodeKind::State && !n.composite) n.done_event = intern("e_done@" + n.fqn);

  for (PendingTransition& p : pending_) {
    TransitionSpec& spec = p.spec;
    const std::string label = where(spec.origin) + "transition " + spec.src + " -> " + spec.tgt + " in " +
                              nodes[static_cast<std::size_t>(p.scope)].fqn;
    if (spec.src.empty() || spec.tgt.empty()) {
      problems.push_back(label + ": needs both src and tgt");
      continue;
    }
    std::string why;
    const int src = resolve(spec.src, p.scope, why);
    if (src < 0) {
      problems.push_back(label + ": unknown source, " + why);
      continue;
    }
    int tgt = resolve(spec.tgt, p.scope, why);
    if (tgt < 0) {
      problems.push_back(label + ": unknown target, " + why);
      continue;
    }
    if (tgt == 0) {
      problems.push_back(label + ": the root cannot be a target");
      continue;
    }
    if (nodes[static_cast<std::size_t>(tgt)].composite) {
      if (nodes[static_cast<std::size_t>(tgt)].initial < 0) {
        problems.push_back(label + ": the target " + nodes[static_cast<std::size_t>(tgt)].fqn +
                           " is composite but has no initial connector; give it a transition from 'initial'");
        continue;
      }
      tgt = nodes[static_cast<std::size_t>(tgt)].initial;
    }
    const bool from_connector = nodes[static_cast<std::size_t>(src)].kind == NodeKind::Connector;
    Chart::Transition t{src, tgt, {}, spec.pn, std::move(spec.guard), std::move(spec.effect), spec.origin,
                        nodes[static_cast<std::size_t>(src)].fqn + " -> " + nodes[static_cast<std::size_t>(tgt)].fqn,
                        -1.0, false, kUnknownEvent};
    for (const std::string& e : spec.events) {
      double seconds = 0.0;
      bool absolute = false;
      std::string canonical;
      if (e.empty()) {
        problems.push_back(label + ": an event name is empty");
      } else if (e == "e_done" && from_connector) {
        problems.push_back(label + ": e_done from a connector never happens (only states complete); move the "
                                   "transition's e_done to the state that leads to the connector");
      } else if (e == "e_done") {
        t.events.push_back(intern("e_done@" + nodes[static_cast<std::size_t>(src)].fqn));
      } else if (parseTimeEvent(e, seconds, absolute, canonical) && from_connector) {
        problems.push_back(label + ": '" + e + "' from a connector never happens (time counts from a state's entry); " +
                           "move it to the state that leads to the connector");
      } else if (!canonical.empty()) {
        if (t.time_spec >= 0.0) problems.push_back(label + ": has two time events; keep one");
        t.time_spec = seconds;
        t.time_absolute = absolute;
        t.time_event = intern(canonical + "@" + nodes[static_cast<std::size_t>(src)].fqn);
        t.events.push_back(t.time_event);
      } else if (e.starts_with("e_after(") || e.starts_with("e_at(")) {
        problems.push_back(label + ": '" + e + "' is not a time event; write e_after(seconds) or e_at(seconds)");
      } else {
        t.events.push_back(intern(e));
      }
    }
    std::sort(t.events.begin(), t.events.end());
    chart_.transitions_.push_back(std::move(t));
  }
  if (!problems.empty()) {
    std::string message = "chart has " + std::to_string(problems.size()) + " problem(s):";
    for (const std::string& p : problems) message += "\n  " + p;
    throw std::invalid_argument(message);
  }
  // Outgoing transitions by pn, higher first; equal pn keep the order they were added in.
  for (std::size_t i = 0; i < chart_.transitions_.size(); ++i)
    nodes[static_cast<std::size_t>(chart_.transitions_[i].src)].transitions.push_back(static_cast<int>(i));
  for (Chart::Node& n : nodes)
    std::stable_sort(n.transitions.begin(), n.transitions.end(), [&](int a, int b) {
      return chart_.transitions_[static_cast<std::size_t>(a)].pn > chart_.transitions_[static_cast<std::size_t>(b)].pn;
    });
  pending_.clear();
  Chart built = std::move(chart_);
  chart_ = Chart{};
  chart_.nodes_.push_back(Chart::Node{NodeKind::State, "root", "root", 0, 0, false, -1, {}, {}, kUnknownEvent});
  return built;
}

}  // namespace cobra::statechart
