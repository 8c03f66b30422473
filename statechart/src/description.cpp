#include "cobra/statechart/description.hpp"

namespace cobra::statechart {

ChartDescription describe(const Chart& chart) {
  ChartDescription out;
  const auto& nodes = chart.nodes();
  out.nodes.reserve(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Chart::Node& n = nodes[i];
    const bool root = static_cast<std::size_t>(n.parent) == i;
    out.nodes.push_back({n.fqn, root ? std::string() : chart.node(n.parent).fqn, n.kind == NodeKind::Connector, n.composite});
  }
  for (const Chart::Node& n : nodes)
    for (const int index : n.transitions) {
      const Chart::Transition& t = chart.transitions().at(static_cast<std::size_t>(index));
      ChartDescription::Transition d;
      d.src = chart.node(t.src).fqn;
      d.tgt = chart.node(t.tgt).fqn;
      for (const EventId id : t.events) d.events.push_back(chart.eventNames().at(id));
      d.pn = t.pn;
      d.guarded = static_cast<bool>(t.guard);
      out.transitions.push_back(std::move(d));
    }
  return out;
}

}  // namespace cobra::statechart
