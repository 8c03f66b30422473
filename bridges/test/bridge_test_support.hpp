#pragma once
// Shared helpers of the socket tests: unique shared memory names, bounded polling on the lockstep
// clock (each step also sleeps 1 ms of wall time, so that the far end's threads make progress),
// and an event collector.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "cobra/bridges/shared_memory.hpp"
#include "cobra/core/core.hpp"

namespace cobra::bridges::test {

/// A POSIX shared memory name unique to this process and call, unlinked when the guard goes.
struct UniqueShm {
  std::string name;
  UniqueShm() {
    static std::atomic<int> counter{0};
    name = "/cobra_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter.fetch_add(1));
  }
  ~UniqueShm() { SharedSegment::unlink(name); }
};

/// Advances `clock` by 1 ms (and sleeps 1 ms) until `done` holds, at most `max_steps` times.
inline bool pollUntil(core::LockstepClock& clock, const std::function<bool()>& done, int max_steps = 3000) {
  using namespace std::chrono_literals;
  for (int i = 0; i < max_steps; ++i) {
    if (done()) return true;
    clock.advance(1ms);
    std::this_thread::sleep_for(1ms);
  }
  return done();
}

/// Collects the events a component emits.
struct EventLog {
  core::InputPort<core::Event> in{"events_in", "", ""};
  std::vector<std::string> names;
  explicit EventLog(core::Component& c) { core::connectPorts(c.events(), in, core::ConnPolicy::buffer(64)); }
  void drain() {
    core::Event e;
    while (in.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
  }
  std::string last() {
    drain();
    return names.empty() ? std::string() : names.back();
  }
};

}  // namespace cobra::bridges::test
