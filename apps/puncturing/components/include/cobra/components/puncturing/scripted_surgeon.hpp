#pragma once
/// @file
/// The surgeon's console for simulated runs: a Bridge component that plays a surgeon script
/// (apps/puncturing/README.md, surgeon.txt) against the two task charts of the puncturing task,
/// and lets a console user say any surgeon event by hand.

#include <chrono>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "cobra/puncturing/plan.hpp"

namespace cobra::components {

/// Interface:
/// - properties `script_file` (the surgeon script, parsed at configure: a bad line refuses
///   configure with "component 'X': FILE:LINE: message"), `max_pending` (1: state-triggered
///   events waiting for their delay at once, reserved at configure), `dropped_events` (1, read
///   only: triggered events lost because max_pending were already waiting);
/// - input ports `needleTaskState`, `usTaskState` (TaskState: the active state of the needle
///   insertion and ultrasound positioning charts; connect them with a buffer policy so that no
///   state of a step is missed);
/// - operation `say(event)`: emits a surgeon event at once (one of puncturing::surgeonEvents(),
///   anything else is an error naming the allowed ones);
/// - the script's events, emitted on `events`: `at T EVENT` at T s after start; `on CHART.STATE
///   EVENT after=S times=N` S s after chart CHART entered a state whose path contains STATE, at
///   most N times (0: every time). On each entry the first line of the script for that state
///   that is not used up fires, as in the charts' test (apps/puncturing/test).
///
/// A state is *entered* when the chart's published path contains STATE and the path it published
/// before did not: the charts publish their active leaf, so entering a composite state is seen
/// at its first leaf, and leaving and re-entering the same leaf between two samples is not seen.
/// Times are on the component's clock (simulated on the lockstep clock, so runs are
/// deterministic); it needs a periodic activity, whose period is the resolution of the delays.
///
/// Real time: updateHook reads the ports, matches the script and emits events without allocating.
class ScriptedSurgeon : public core::Component {
 public:
  explicit ScriptedSurgeon(std::string name);

  const puncturing::SurgeonScript& script() const { return script_; }

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  struct Pending {
    std::chrono::nanoseconds due;
    std::size_t action;  // index into script_.actions
  };

  void say(const std::string& event);
  /// Chart `chart` ("needle"/"us") published `path` after `previous`: schedules what the script says.
  void changed(std::string_view chart, std::string_view previous, std::string_view path) noexcept;

  core::Property<std::string> script_file_{"script_file", "", "", "surgeon script (surgeon.txt format)"};
  core::Property<int> max_pending_{"max_pending", 64, "1", "triggered events waiting for their delay at once"};
  core::Property<int> dropped_{"dropped_events", 0, "1", "triggered events lost because max_pending were waiting"};

  core::InputPort<core::TaskState> needle_state_{"needleTaskState", "active state of the needle insertion chart", ""};
  core::InputPort<core::TaskState> us_state_{"usTaskState", "active state of the ultrasound positioning chart", ""};

  puncturing::SurgeonScript script_;
  std::vector<int> used_;          // per action: times fired (or scheduled)
  std::vector<char> fired_now_;    // per action: scheduled by the current state change
  std::vector<Pending> pending_;   // capacity max_pending, reserved at configure
  core::TaskState last_[2];        // last path seen per chart (needle, us)
  core::TaskState sample_;
  std::chrono::nanoseconds start_{0};
};

}  // namespace cobra::components
