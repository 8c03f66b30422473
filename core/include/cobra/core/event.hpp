#pragma once
/// @file
/// The logic-data `Event` carried by `events` ports between components and supervisors.

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

}  // namespace cobra::core
