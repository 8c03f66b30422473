#pragma once
/// @file
/// The logic data of coordination: the `Event` carried by `events` ports between components and
/// supervisors, and the `TaskState` a supervisor publishes.

#include <chrono>

#include "cobra/core/bounded_string.hpp"

namespace cobra::core {

/// An event: what happened (`name`, e.g. "e_plan_done"), who said it (`source`, a component
/// name) and when (`stamp`, nanoseconds on the emitting component's clock: wall-clock time for
/// real activities, simulated time on the lockstep clock). Trivially copyable: sending one
/// through a port never allocates. Names longer than 63 characters are truncated.
struct Event {
  BoundedString<63> name;
  BoundedString<63> source;
  std::chrono::nanoseconds stamp{0};

  friend bool operator==(const Event&, const Event&) = default;
};

/// The active state of a task chart, as its full path ("root.opening.approach"): what a
/// Supervisor's `taskState` port carries (thesis §4.5.10). Paths longer than 127 characters are
/// truncated.
struct TaskState {
  BoundedString<127> path;

  friend bool operator==(const TaskState&, const TaskState&) = default;
};

}  // namespace cobra::core
