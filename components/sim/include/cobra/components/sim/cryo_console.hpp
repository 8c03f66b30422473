#pragma once
/// @file
/// The simulated cryoablation console (thesis ch. 4: the console runs the freeze cycle once the
/// needle is placed): a sim-world actor that the task chart asks for a cycle with an event, that
/// freezes and thaws the patient through a port and says when the cycle is over.

#include <chrono>
#include <string>

#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"

namespace cobra::components {

/// Bridge (it stands for a device of the operating room). Needs a periodic activity: its period
/// is the resolution of the freeze duration.
///
/// One cycle: an event named `start_event` on `inputEvents` starts it; the console writes 1 on
/// `freezeCommand` (the patient freezes around the needle tip), after `freeze_duration` s writes 0
/// (the patient thaws), then, as soon as the patient's `iceballRadius` is at most `thawed_radius`,
/// emits `done_event` on `events` and is idle again. A start request during a cycle is ignored
/// (a console runs one cycle at a time); other events are ignored.
///
/// Properties: `start_event` (default "e_cryo_start"), `done_event` (default "e_cryo_done"),
/// `freeze_duration` (s, > 0), `thawed_radius` (m, >= 0: the radius at which the console reports
/// the thaw; above the patient's release radius the needle may still be held by the ice, which is
/// what the task's extraction check is for).
/// Ports: in `inputEvents` (event port: the requests), in `iceballRadius` (m, the patient's iceball:
/// the console's thaw sensor; must be connected), out `freezeCommand` (1: freeze, 0: thaw; to the
/// patient's freezeCommand), out `cyclePhase` (0 idle, 1 freezing, 2 thawing; written on change).
/// Real time: updateHook allocates nothing and never blocks.
class CryoConsole : public core::Component {
 public:
  explicit CryoConsole(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  enum class Phase { Idle = 0, Freezing = 1, Thawing = 2 };
  void enter(Phase phase) noexcept;

  core::Property<std::string> start_event_{"start_event", "e_cryo_start", "", "event that starts a freeze cycle"};
  core::Property<std::string> done_event_{"done_event", "e_cryo_done", "", "event emitted when the cycle has thawed"};
  core::Property<double> freeze_duration_{"freeze_duration", 600.0, "s", "length of the freeze phase, > 0"};
  core::Property<double> thawed_radius_{"thawed_radius", 0.001, "m",
                                        "iceball radius at or below which the thaw is reported, >= 0"};

  core::InputPort<core::Event> input_events_{"inputEvents", "requests (start_event starts a cycle)", ""};
  core::InputPort<double> iceball_radius_{"iceballRadius", "the patient's iceball radius (thaw sensor)", "m"};
  core::OutputPort<double> freeze_command_{"freezeCommand", "1: freeze, 0: thaw (to the patient)", "1"};
  core::OutputPort<double> cycle_phase_{"cyclePhase", "0 idle, 1 freezing, 2 thawing", "1"};

  core::BoundedString<63> start_name_, done_name_;  // the event names, copied at configure
  std::chrono::nanoseconds thaw_at_{0};
  Phase phase_ = Phase::Idle;
};

}  // namespace cobra::components
