// Shared by the statechart tests: a transition as written, and the thesis' Fig. 3.2 chart (with
// its last transition's target spelt `tgt`: the listing has `tqt`).
#pragma once

#include <string>
#include <vector>

#include "cobra/statechart/chart.hpp"

namespace cobra::statechart::test {

inline TransitionSpec trans(std::string src, std::string tgt, std::vector<std::string> events = {}, std::string origin = {}) {
  TransitionSpec t;
  t.src = std::move(src);
  t.tgt = std::move(tgt);
  t.events = std::move(events);
  t.origin = std::move(origin);
  return t;
}

inline Chart figure32() {
  ChartBuilder b;
  b.addState("root", "on");
  b.addState("root.on", "moving");
  b.addState("root.on", "waiting");
  b.addTransition("root.on", trans("initial", "waiting"));
  b.addTransition("root.on", trans("waiting", "moving", {"e_start"}));
  b.addTransition("root.on", trans("moving", "waiting", {"e_stop"}));
  b.addState("root", "error");
  b.addState("root", "fatal_error");
  b.addTransition("root", trans("initial", "on"));
  b.addTransition("root", trans("on", "error", {"e_error"}));
  b.addTransition("root", trans("error", "on", {"e_error_fixed"}));
  b.addTransition("root", trans("error", "fatal_error", {"e_fatal_error"}));
  b.addTransition("root", trans("fatal_error", "initial", {"e_reset"}));
  return b.build();
}

}  // namespace cobra::statechart::test
