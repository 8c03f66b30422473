#include "stall_watch.hpp"

#include <algorithm>
#include <cstdio>

#include "cobra/statechart/description.hpp"

namespace cobra::run {
namespace {

std::string at(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f s", t);
  return text;
}

// The events of the transitions that leave `state` or one of its ancestors (what can end the
// wait), in the chart's order, each once; "any event" for a transition without events.
std::vector<std::string> awaited(const statechart::Chart& chart, const std::string& state) {
  std::vector<std::string> events;
  for (const statechart::ChartDescription::Transition& t : statechart::describe(chart).transitions) {
    const bool leaves = state == t.src || (state.starts_with(t.src) && state.size() > t.src.size() && state[t.src.size()] == '.');
    if (!leaves) continue;
    if (t.events.empty() && std::find(events.begin(), events.end(), "any event") == events.end()) events.push_back("any event");
    for (const std::string& e : t.events)
      if (std::find(events.begin(), events.end(), e) == events.end()) events.push_back(e);
  }
  return events;
}

}  // namespace

void StallWatch::entered(double t) {
  since_ = t;
  said_ = false;
  heard_.clear();
}

void StallWatch::heard(const std::string& event, const std::string& source, double t) {
  if (heard_.size() >= kMaxHeard) return;
  if (std::any_of(heard_.begin(), heard_.end(), [&](const Heard& h) { return h.event == event; })) return;
  heard_.push_back({event, source, t});
}

bool StallWatch::due(double t, double after) {
  if (said_ || after <= 0.0 || t - since_ < after) return false;
  said_ = true;
  return true;
}

std::string StallWatch::text(const std::string& name, const std::string& state, const statechart::Chart* chart) const {
  std::string out = name + " chart in " + state + " since " + at(since_);
  if (chart != nullptr) {
    const std::vector<std::string> events = awaited(*chart, state);
    out += events.empty() ? "; no transition leaves it" : "; it waits for ";
    for (std::size_t i = 0; i < events.size(); ++i) out += (i > 0 ? ", " : "") + events[i];
  }
  if (heard_.empty()) return out + "; no event arrived there";
  out += "; heard there with no change of state: ";
  for (std::size_t i = 0; i < heard_.size(); ++i)
    out += (i > 0 ? ", " : "") + heard_[i].event + " (" + heard_[i].source + " at " + at(heard_[i].t) + ")";
  return out;
}

}  // namespace cobra::run
