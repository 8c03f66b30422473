#include "cobra/components/sim/cryo_console.hpp"

#include <cmath>

namespace cobra::components {

CryoConsole::CryoConsole(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Simulated cryoablation console (thesis ch. 4): on request freezes the patient for freeze_duration s, "
                "lets it thaw and reports the thaw") {
  addProperty(start_event_);
  addProperty(done_event_);
  addProperty(freeze_duration_);
  addProperty(thawed_radius_);
  addEventPort(input_events_);
  addPort(iceball_radius_);
  addPort(freeze_command_);
  addPort(cycle_phase_);
}

bool CryoConsole::configureHook() {
  if (!(freeze_duration_() > 0.0) || !std::isfinite(freeze_duration_()))
    return refuse("property freeze_duration is " + std::to_string(freeze_duration_()) + " s; expected > 0 s");
  if (!(thawed_radius_() >= 0.0) || !std::isfinite(thawed_radius_()))
    return refuse("property thawed_radius is " + std::to_string(thawed_radius_()) + " m; expected >= 0 m");
  for (const auto& [property, name] : {std::pair{&start_event_, "start_event"}, std::pair{&done_event_, "done_event"}}) {
    const std::string& value = (*property)();
    if (value.empty() || value.size() > core::BoundedString<63>::capacity())
      return refuse("property " + std::string(name) + " is '" + value + "'; expected an event name of 1 to 63 characters");
  }
  start_name_.assign(start_event_());
  done_name_.assign(done_event_());
  return true;
}

bool CryoConsole::startHook() {
  if (!iceball_radius_.connected())
    return refuse("input port iceballRadius is not connected; connect the patient's iceball radius (m), the "
                  "console's thaw sensor (e.g. Patient.iceballRadius)");
  phase_ = Phase::Idle;
  core::Event stale;
  while (input_events_.readNew(stale) == core::FlowStatus::NewData) {
  }  // requests sent before the start are not this run's
  cycle_phase_.write(static_cast<double>(Phase::Idle));
  return true;
}

void CryoConsole::enter(Phase phase) noexcept {
  phase_ = phase;
  cycle_phase_.write(static_cast<double>(phase));
}

void CryoConsole::updateHook() {
  core::Event request;
  while (input_events_.readNew(request) == core::FlowStatus::NewData) {
    if (request.name == start_name_ && phase_ == Phase::Idle) {
      freeze_command_.write(1.0);
      thaw_at_ = now() + std::chrono::nanoseconds(static_cast<std::int64_t>(freeze_duration_() * 1e9));
      enter(Phase::Freezing);
    }
  }
  if (phase_ == Phase::Freezing && now() >= thaw_at_) {
    freeze_command_.write(0.0);
    enter(Phase::Thawing);
  }
  double radius = 0.0;
  if (phase_ == Phase::Thawing && iceball_radius_.read(radius) != core::FlowStatus::NoData &&
      radius <= thawed_radius_()) {
    emitEvent(done_name_.view());
    enter(Phase::Idle);
  }
}

}  // namespace cobra::components
