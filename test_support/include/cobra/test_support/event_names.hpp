#pragma once
// Reads the events a component emitted, for unit tests of components (needs cobra::core; not part
// of any library).

#include <string>
#include <vector>

#include "cobra/core/event.hpp"
#include "cobra/core/port.hpp"

namespace cobra::test_support {

/// The names of every event waiting on `events`, oldest first; the port's buffer is empty after.
/// Connect it to the component's `events` with a buffer (core::ConnPolicy::buffer(n)) so that none
/// is overwritten between two reads.
inline std::vector<std::string> takeEventNames(core::InputPort<core::Event>& events) {
  std::vector<std::string> names;
  core::Event e;
  while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
  return names;
}

}  // namespace cobra::test_support
