#pragma once
// Shared helpers of the socket tests: unique shared memory names, bounded polling on the lockstep
// clock (each step also sleeps 1 ms of wall time, so that the far end's threads make progress),
// an event collector, and a start configuration of the two-tool (suturing) I-SUR.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "cobra/bridges/shared_memory.hpp"
#include "cobra/core/core.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/test_support/event_names.hpp"

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
    for (std::string& name : test_support::takeEventNames(in)) names.push_back(std::move(name));
  }
  std::string last() {
    drain();
    return names.empty() ? std::string() : names.back();
  }
};

/// Joints (14, rad / m) of the suturing I-SUR that its split IK gives back for their own tool poses
/// (a fixed point of inverse ∘ forward, so a Cartesian command of the current poses is a zero
/// step): the needle arm at the puncturing setup's elbow (q6 = 0.85, q7 = 0.55 rad), the gripper
/// arm bent away from its wrist singularity (q13 = 0.8 rad), the delta sliders mid-stroke.
inline std::vector<double> suturingStart() {
  kinematics::IsurSuturingSolver solver;
  KDL::JntArray guess(kinematics::IsurSuturingSolver::kJoints);
  for (unsigned i = 0; i < guess.rows(); ++i) guess(i) = 0.5 * (solver.limits().lower[i] + solver.limits().upper[i]);
  guess(5) = 0.85;
  guess(6) = 0.55;
  const double left[6] = {0.3, -0.6, 0.4, 0.2, 0.8, 0.1};
  for (unsigned i = 0; i < 6; ++i) guess(8 + i) = left[i];
  KDL::Frame stitch, gripper;
  KDL::JntArray q(guess.rows());
  if (solver.forward(guess, stitch, gripper) != kinematics::IkStatus::Ok ||
      solver.inverse(stitch, gripper, guess, q) != kinematics::IkStatus::Ok)
    return {};
  return std::vector<double>(q.data.data(), q.data.data() + q.rows());
}

}  // namespace cobra::bridges::test
