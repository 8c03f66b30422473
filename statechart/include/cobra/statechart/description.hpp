#pragma once
/// @file
/// A read-only description of a built `Chart` in plain data: every state and connector by its
/// full path and every transition with the names of its events. For viewers that show a chart
/// (cobra studio's console lists each chart's states and offers the inputs whose events some
/// active state waits for) without depending on the engine's indices. Built at configure time:
/// it allocates; a `Machine` never needs it.

#include <string>
#include <vector>

#include "cobra/statechart/chart.hpp"

namespace cobra::statechart {

struct ChartDescription {
  struct Node {
    std::string path;    ///< full path: "root", "root.a.b"
    std::string parent;  ///< the parent's path ("" for the root)
    bool connector = false;
    bool composite = false;  ///< has sub-nodes
  };
  struct Transition {
    std::string src;  ///< a state's or a connector's path
    std::string tgt;  ///< a leaf state or a connector (a composite target is its `initial`)
    /// Event names as the machine matches them ("e_recover", "e_done@root.a",
    /// "e_after(1.5)@root.a"); empty: any event triggers it.
    std::vector<std::string> events;
    int pn = 0;
    bool guarded = false;  ///< has a guard: the events alone may not be enough
  };
  std::vector<Node> nodes;  ///< in the chart's order: the root first, a parent before its children
  /// Outgoing transitions of each node in the order the machine tries them (pn, then as added).
  std::vector<Transition> transitions;
};

/// Describes `chart`. Allocates; call at configure time.
ChartDescription describe(const Chart& chart);

}  // namespace cobra::statechart
