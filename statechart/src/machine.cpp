#include "cobra/statechart/machine.hpp"

#include <algorithm>
#include <cstring>
#include <exception>

namespace cobra::statechart {
namespace {

std::size_t at(int index) { return static_cast<std::size_t>(index); }

constexpr std::string_view kInitEvent = "e_init_fsm";

/// Internal events waiting at once, at most: e_init_fsm or one e_done (a step enters at most one
/// leaf, and each step takes every queued event), plus one per time-event transition.
std::size_t internalReserve(const Chart& chart) {
  return 1 + static_cast<std::size_t>(std::count_if(chart.transitions().begin(), chart.transitions().end(),
                                                    [](const Chart::Transition& t) { return t.time_spec >= 0.0; }));
}

}  // namespace

Machine::Machine(const Chart& chart, std::function<std::chrono::nanoseconds()> clock, std::size_t queue_capacity)
    : chart_(&chart),
      clock_(std::move(clock)),
      capacity_(std::max<std::size_t>(queue_capacity, 1)),
      active_child_(chart.nodes().size(), -1),
      leaf_done_(chart.nodes().size(), 0),
      doo_restart_(chart.nodes().size(), 1),
      entry_time_(chart.nodes().size(), std::chrono::nanoseconds(0)),
      time_fired_(chart.transitions().size(), 0),
      timed_path_(chart.nodes().size(), 0),
      queue_(capacity_ + internalReserve(chart)),
      current_(queue_.size()),
      current_entries_(queue_.size()),
      path_(chart.nodes().size() + 1),
      down_(chart.nodes().size() + 1) {
  for (std::size_t n = 0; n < timed_path_.size(); ++n) {
    for (int s = static_cast<int>(n);; s = chart.nodes()[static_cast<std::size_t>(s)].parent) {
      for (int ti : chart.nodes()[static_cast<std::size_t>(s)].transitions)
        if (chart.transitions()[static_cast<std::size_t>(ti)].time_spec >= 0.0) timed_path_[n] = 1;
      if (s == 0 || timed_path_[n]) break;
    }
  }
  reset();
}

RaiseStatus Machine::raise(std::string_view event) noexcept {
  if (event.size() > kMaxEventName) return RaiseStatus::NameTooLong;
  if (queue_size_ - internal_queued_ >= capacity_) return RaiseStatus::QueueFull;
  push(chart_->eventId(event), event);
  return RaiseStatus::Queued;
}

void Machine::raiseInternal(EventId id, std::string_view name) noexcept {
  // Never full (the reserve is sized for the worst case) and never too long (names of the chart).
  if (queue_size_ == queue_.size() || name.size() > kMaxEventName) return;
  push(id, name);
  ++internal_queued_;
}

void Machine::push(EventId id, std::string_view name) noexcept {
  QueuedEvent& slot = queue_[queue_size_];
  slot.id = id;
  slot.length = name.size();
  std::memcpy(slot.text, name.data(), name.size());
  ++queue_size_;
}

void Machine::reset() noexcept {
  entered_ = false;
  active_leaf_ = -1;
  std::fill(active_child_.begin(), active_child_.end(), -1);
  std::fill(leaf_done_.begin(), leaf_done_.end(), 0);
  std::fill(doo_restart_.begin(), doo_restart_.end(), 1);
  std::fill(time_fired_.begin(), time_fired_.end(), 0);
  queue_size_ = internal_queued_ = 0;
  raiseInternal(chart_->eventId(kInitEvent), kInitEvent);  // as rFSM's init and reset
}

std::string_view Machine::activeLeaf() const noexcept {
  return active_leaf_ < 0 ? std::string_view() : std::string_view(chart_->node(active_leaf_).fqn);
}

bool Machine::isActive(std::string_view fqn) const noexcept {
  if (!entered_) return false;
  for (int s = 0; s >= 0; s = active_child_[at(s)]) {
    if (chart_->nodes()[at(s)].fqn == fqn) return true;
    if (active_child_[at(s)] == s) break;
  }
  return false;
}

template <class Callback>
bool Machine::guarded(const char* callback, std::string_view element, Callback&& call) noexcept {
  try {
    call();
    return true;
  } catch (const std::exception& e) {
    failed(callback, element, e.what());
  } catch (...) {
    failed(callback, element, "unknown exception");
  }
  return false;
}

void Machine::failed(const char* callback, std::string_view element, const char* what) noexcept {
  if (observer_ != nullptr) observer_->callbackFailed(callback, element, what);
}

void Machine::checkTimeEvents() noexcept {
  if (!entered_ || !timed_path_[at(active_leaf_ < 0 ? 0 : active_leaf_)]) return;
  const auto now = clock_ ? clock_() : std::chrono::nanoseconds(0);
  // From the active leaf up to the root, as rFSM's check_act_timeevents.
  for (int s = active_leaf_ < 0 ? 0 : active_leaf_;; s = chart_->nodes()[at(s)].parent) {
    for (int ti : chart_->nodes()[at(s)].transitions) {
      const Chart::Transition& t = chart_->transitions()[at(ti)];
      if (t.time_spec < 0.0 || time_fired_[at(ti)]) continue;
      const auto spec = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(t.time_spec));
      const auto deadline = t.time_absolute ? spec : entry_time_[at(s)] + spec;
      if (now > deadline) {  // strictly later, as rFSM's timeevent
        raiseInternal(t.time_event, chart_->eventNames()[t.time_event]);
        time_fired_[at(ti)] = 1;
      }
    }
    if (s == 0) break;
  }
}

bool Machine::enabled(const Chart::Transition& t, const StepEvents& events) noexcept {
  if (t.guard) {  // the guard first, whatever the events (rFSM's order)
    bool open = false;
    if (!guarded("guard", t.text, [&] { open = t.guard(events); }) || !open) return false;
  }
  if (t.events.empty()) return true;
  for (std::size_t i = 0; i < events.size(); ++i)
    if (events.id(i) != kUnknownEvent && std::binary_search(t.events.begin(), t.events.end(), events.id(i)))
      return true;
  return false;
}

bool Machine::findPath(int node, const StepEvents& events, std::size_t depth, bool record) noexcept {
  bool found = false;
  for (int ti : chart_->nodes()[at(node)].transitions) {
    const Chart::Transition& t = chart_->transitions()[at(ti)];
    if (!enabled(t, events)) continue;
    const bool to_leaf = chart_->nodes()[at(t.tgt)].kind == NodeKind::State;
    // A path through connectors longer than the chart has nodes is a connector cycle: not taken.
    const bool complete = to_leaf || (depth + 1 < path_.size() && findPath(t.tgt, events, depth + 1, record && !found));
    if (complete && !found && record) {
      path_[depth] = ti;
      if (to_leaf) path_length_ = depth + 1;
    }
    found = found || complete;
  }
  return found;
}

int Machine::lca(int a, int b) const noexcept {
  const auto& nodes = chart_->nodes();
  while (nodes[at(a)].depth > nodes[at(b)].depth) a = nodes[at(a)].parent;
  while (nodes[at(b)].depth > nodes[at(a)].depth) b = nodes[at(b)].parent;
  while (a != b) {
    a = nodes[at(a)].parent;
    b = nodes[at(b)].parent;
  }
  return a;
}

void Machine::exit(int node) noexcept {
  const Chart::Node& n = chart_->nodes()[at(node)];
  if (n.kind != NodeKind::State) return;
  if (n.composite && active_child_[at(node)] >= 0 && active_child_[at(node)] != node) exit(active_child_[at(node)]);
  if (active_child_[at(n.parent)] == node) active_child_[at(n.parent)] = -1;
  if (n.callbacks.exit) {
    guarded("exit", n.fqn, n.callbacks.exit);
  }
  if (!n.composite) active_leaf_ = -1;
  if (observer_ != nullptr) observer_->exited(n.fqn);
}

void Machine::enter(int node) noexcept {
  const Chart::Node& n = chart_->nodes()[at(node)];
  if (n.kind != NodeKind::State) return;
  active_child_[at(n.parent)] = node;
  entry_time_[at(node)] = clock_ ? clock_() : std::chrono::nanoseconds(0);
  for (int ti : n.transitions) time_fired_[at(ti)] = 0;
  if (n.callbacks.entry) {
    guarded("entry", n.fqn, n.callbacks.entry);
  }
  if (!n.composite) {
    active_leaf_ = node;
    doo_restart_[at(node)] = 1;
    leaf_done_[at(node)] = n.callbacks.doo ? 0 : 1;
    if (!n.callbacks.doo) raiseInternal(n.done_event, chart_->eventNames()[n.done_event]);
  }
  if (observer_ != nullptr) observer_->entered(n.fqn);
}

void Machine::execute(const Chart::Transition& t, const StepEvents& events) noexcept {
  const auto& nodes = chart_->nodes();
  const int common = lca(nodes[at(t.src)].parent, nodes[at(t.tgt)].parent);
  int top = t.src;  // the highest node below the LCA on the source's side
  while (nodes[at(top)].parent != common) top = nodes[at(top)].parent;
  exit(top);
  if (observer_ != nullptr) observer_->transitionTaken(t);
  if (t.effect) {
    guarded("effect", t.text, [&] { t.effect(events); });
  }
  std::size_t count = 0;
  for (int n = t.tgt; n != common; n = nodes[at(n)].parent) down_[count++] = n;
  while (count > 0) enter(down_[--count]);
}

void Machine::executePath(const StepEvents& events) noexcept {
  for (std::size_t i = 0; i < path_length_; ++i) execute(chart_->transitions()[at(path_[i])], events);
}

StepResult Machine::step() noexcept {
  checkTimeEvents();
  const std::size_t count = queue_size_;
  queue_.swap(current_);  // a step takes every queued event: no copy, and the queue starts empty
  queue_size_ = internal_queued_ = 0;
  for (std::size_t i = 0; i < count; ++i)
    current_entries_[i] = {current_[i].id, std::string_view(current_[i].text, current_[i].length)};
  const StepEvents events(std::span<const StepEvents::Entry>(current_entries_.data(), count));

  if (!entered_) {
    const int initial = chart_->nodes()[0].initial;
    if (initial < 0 || !findPath(initial, events, 0, true)) return StepResult::CannotEnter;
    enter(0);
    active_child_[0] = -1;
    entered_ = true;
    executePath(events);
    return StepResult::Entered;
  }
  if (count > 0) {
    for (int s = 0; s >= 0;) {
      if (findPath(s, events, 0, true)) {
        executePath(events);
        return StepResult::Transitioned;
      }
      const int child = active_child_[at(s)];
      s = child == s ? -1 : child;
    }
    if (observer_ != nullptr) observer_->eventsIgnored(events);
    return StepResult::EventsIgnored;
  }
  const int leaf = active_leaf_;
  if (leaf < 0 || leaf_done_[at(leaf)]) return queue_size_ > 0 ? StepResult::DooRan : StepResult::Idle;
  const Chart::Node& n = chart_->nodes()[at(leaf)];
  DooStatus status = DooStatus::Done;
  if (!guarded("doo", n.fqn, [&] { status = n.callbacks.doo(doo_restart_[at(leaf)] != 0); })) {
    leaf_done_[at(leaf)] = 1;  // a failing doo ends, as in rFSM, but raises no e_done
    return queue_size_ > 0 ? StepResult::DooRan : StepResult::Idle;
  }
  doo_restart_[at(leaf)] = 0;
  if (status == DooStatus::Done) {
    leaf_done_[at(leaf)] = 1;
    raiseInternal(n.done_event, chart_->eventNames()[n.done_event]);
  }
  if (status == DooStatus::Busy) return StepResult::DooRan;
  return queue_size_ > 0 ? StepResult::DooRan : StepResult::Idle;
}

bool Machine::run(std::size_t max_steps) noexcept {
  for (std::size_t i = 0; i < max_steps; ++i) {
    const StepResult r = step();
    if (r == StepResult::Idle) return true;
    if (r == StepResult::CannotEnter) return false;
  }
  return false;
}

}  // namespace cobra::statechart
