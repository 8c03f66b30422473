#pragma once
// Components used by the deploy tests: ones whose hooks fail on demand and ones with every
// combination of role and data kind the linter must judge.

#include <kdl/frames.hpp>

#include <stdexcept>

#include "cobra/core/component.hpp"
#include "cobra/deploy/package_registry.hpp"

namespace cobra::deploy::test {

/// Calculation with a double in/out whose configureHook or startHook fails when its properties
/// say so (refuse: returns false; throw: throws).
class Faulty : public core::Component {
 public:
  explicit Faulty(std::string name) : Component(std::move(name), core::Role::Calculation, "fails on demand") {
    addEventPort(in_);
    addPort(out_);
    addProperty(refuse_configure_);
    addProperty(throw_configure_);
    addProperty(refuse_start_);
  }
  int cleanups = 0;

 protected:
  bool configureHook() override {
    if (throw_configure_()) throw std::runtime_error("calibration file missing");
    return !refuse_configure_();
  }
  bool startHook() override { return !refuse_start_(); }
  void cleanupHook() override { ++cleanups; }
  void updateHook() override {
    double u = 0.0;
    while (in_.read(u) == core::FlowStatus::NewData) out_.write(u);
  }

 private:
  core::InputPort<double> in_{"in", "signal", "1"};
  core::OutputPort<double> out_{"out", "signal", "1"};
  core::Property<bool> refuse_configure_{"refuse_configure", false, "", "configureHook returns false"};
  core::Property<bool> throw_configure_{"throw_configure", false, "", "configureHook throws"};
  core::Property<bool> refuse_start_{"refuse_start", false, "", "startHook returns false"};
};

/// A Supervision component as the thesis draws it: events in, events out.
class TaskSupervisor : public core::Component {
 public:
  explicit TaskSupervisor(std::string name) : Component(std::move(name), core::Role::Supervision, "task supervisor") {
    addEventPort(input_events_);
    addPort(output_events_);
  }

 private:
  core::InputPort<core::Event> input_events_{"inputEvents", "events of the components", ""};
  core::OutputPort<core::Event> output_events_{"outputEvents", "events for the other supervisors", ""};
};

/// A Supervision component that (wrongly) reads a pose.
class PoseWatchingSupervisor : public core::Component {
 public:
  explicit PoseWatchingSupervisor(std::string name)
      : Component(std::move(name), core::Role::Supervision, "reads pure data: a role violation") {
    addPort(pose_);
    addPort(level_);
  }

 private:
  core::InputPort<KDL::Frame> pose_{"pose", "tool pose", "m"};
  core::InputPort<double> level_{"level", "a level", "1"};
};

/// A Calculation component that (wrongly) writes events on a port of its own and reads events.
class ChattyCalculation : public core::Component {
 public:
  explicit ChattyCalculation(std::string name)
      : Component(std::move(name), core::Role::Calculation, "writes logic data besides its events port") {
    addPort(pose_out_);
    addPort(status_);
    addPort(trigger_);
  }

 private:
  core::OutputPort<KDL::Frame> pose_out_{"pose", "a pose", "m"};
  core::OutputPort<core::Event> status_{"status", "task-like status events", ""};
  core::InputPort<core::Event> trigger_{"trigger", "events in", ""};
};

/// A Decision component that (wrongly) writes pure data.
class LeakyDecision : public core::Component {
 public:
  explicit LeakyDecision(std::string name) : Component(std::move(name), core::Role::Decision, "writes a number") {
    addPort(in_);
    addPort(out_);
  }

 private:
  core::InputPort<double> in_{"in", "signal", "1"};
  core::OutputPort<double> out_{"out", "signal", "1"};
};

/// A Bridge that reads pure data and writes events: changes the kind, a violation.
class AlarmBridge : public core::Component {
 public:
  explicit AlarmBridge(std::string name) : Component(std::move(name), core::Role::Bridge, "pure in, logic out") {
    addPort(in_);
    addPort(alarm_);
    addPort(echo_);
  }

 private:
  core::InputPort<double> in_{"in", "signal", "1"};
  core::OutputPort<core::Event> alarm_{"alarm", "events", ""};
  core::OutputPort<double> echo_{"echo", "the signal, re-sent", "1"};
};

/// A Bridge without inputs (a sensor): may write either kind.
class SensorBridge : public core::Component {
 public:
  explicit SensorBridge(std::string name) : Component(std::move(name), core::Role::Bridge, "a sensor") {
    addPort(force_);
    addPort(contact_);
  }

 private:
  core::OutputPort<double> force_{"force", "measured force", "N"};
  core::OutputPort<core::Event> contact_{"contact", "contact events", ""};
};

/// Registers every type above as the package "deploy_test_parts".
inline void registerTestParts(PackageBuilder& package) {
  package.component<Faulty>("Faulty", "fails on demand")
      .component<TaskSupervisor>("TaskSupervisor", "events in, events out")
      .component<PoseWatchingSupervisor>("PoseWatchingSupervisor", "reads pure data")
      .component<ChattyCalculation>("ChattyCalculation", "writes logic data")
      .component<LeakyDecision>("LeakyDecision", "writes pure data")
      .component<AlarmBridge>("AlarmBridge", "pure in, logic out")
      .component<SensorBridge>("SensorBridge", "a sensor");
}

}  // namespace cobra::deploy::test
