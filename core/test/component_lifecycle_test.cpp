// Unit tests of the component lifecycle (component.hpp): every transition, every refusal,
// hooks that refuse or throw, Exception/FatalError with their events, recovery, and name checks.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::messageOf;

enum class Hook { None, Configure, Start, Update, Stop, Cleanup, Exception };

/// A component whose hooks record their calls and can be told to refuse or throw.
class Hooked : public Component {
 public:
  explicit Hooked(std::string name = "H") : Component(std::move(name), Role::Calculation, "lifecycle probe") {}
  Hook throw_in = Hook::None;
  Hook also_throw_in = Hook::None;
  bool configure_ok = true;
  bool start_ok = true;
  std::vector<std::string> calls;

 protected:
  bool configureHook() override { return record("configure", Hook::Configure) && configure_ok; }
  bool startHook() override { return record("start", Hook::Start) && start_ok; }
  void updateHook() override { record("update", Hook::Update); }
  void stopHook() override { record("stop", Hook::Stop); }
  void cleanupHook() override { record("cleanup", Hook::Cleanup); }
  void exceptionHook() override { record("exception", Hook::Exception); }

 private:
  bool record(const std::string& hook, Hook which) {
    calls.push_back(hook);
    if (throw_in == which || also_throw_in == which) throw std::runtime_error(hook + " exploded");
    return true;
  }
};

/// An input connected to a component's `events` port, drained into names and sources.
struct EventWatch {
  explicit EventWatch(Component& c) { connect(c.events(), in, ConnPolicy::buffer(16)); }
  std::vector<Event> drain() {
    std::vector<Event> out;
    Event e;
    while (in.read(e) == FlowStatus::NewData) out.push_back(e);
    return out;
  }
  InputPort<Event> in{"watch", "events of the component under test", ""};
};

void step(Component& c) { dynamic_cast<SlaveActivity&>(c.activity()).step(); }

// --- normal transitions -----------------------------------------------------------------------

TEST(Lifecycle, FullCycleRunsEachHookInOrder) {
  Hooked h;
  EXPECT_EQ(h.state(), State::PreOperational);
  ASSERT_TRUE(h.configure());
  EXPECT_EQ(h.state(), State::Stopped);
  ASSERT_TRUE(h.start());
  EXPECT_EQ(h.state(), State::Running);
  EXPECT_TRUE(h.isRunning());
  step(h);
  step(h);
  EXPECT_EQ(h.updateCount(), 2U);
  ASSERT_TRUE(h.stop());
  EXPECT_EQ(h.state(), State::Stopped);
  step(h);  // a stopped component does not update
  EXPECT_EQ(h.updateCount(), 2U);
  ASSERT_TRUE(h.cleanup());
  EXPECT_EQ(h.state(), State::PreOperational);
  EXPECT_EQ(h.calls, (std::vector<std::string>{"configure", "start", "update", "update", "stop", "cleanup"}));
  EXPECT_EQ(h.lastError(), "");
}

TEST(Lifecycle, ConfigureAgainFromStopped) {
  Hooked h;
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.configure());
  EXPECT_EQ(h.state(), State::Stopped);
  EXPECT_EQ(h.calls, (std::vector<std::string>{"configure", "configure"}));
}

TEST(Lifecycle, RestartAfterStop) {
  Hooked h;
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.start());
  ASSERT_TRUE(h.stop());
  ASSERT_TRUE(h.start());
  EXPECT_EQ(h.state(), State::Running);
  ASSERT_TRUE(h.stop());
}

TEST(Lifecycle, StateAndRoleNames) {
  EXPECT_EQ(toString(State::PreOperational), "PreOperational");
  EXPECT_EQ(toString(State::Stopped), "Stopped");
  EXPECT_EQ(toString(State::Running), "Running");
  EXPECT_EQ(toString(State::Exception), "Exception");
  EXPECT_EQ(toString(State::FatalError), "FatalError");
  EXPECT_EQ(toString(Role::Calculation), "Calculation");
  EXPECT_EQ(toString(Role::Supervision), "Supervision");
  EXPECT_EQ(toString(Role::Decision), "Decision");
  EXPECT_EQ(toString(Role::Bridge), "Bridge");
}

// --- refused transitions ----------------------------------------------------------------------

TEST(Lifecycle, StartUnconfiguredIsRefused) {
  Hooked h("Arm");
  const Result r = h.start();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "component 'Arm'");
  EXPECT_CONTAINS(r.message, "PreOperational");
  EXPECT_CONTAINS(r.message, "configure it first");
  EXPECT_EQ(h.state(), State::PreOperational);
  EXPECT_TRUE(h.calls.empty());
}

TEST(Lifecycle, StopWhenNotRunningIsRefused) {
  Hooked h;
  Result r = h.stop();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "cannot stop: it is PreOperational; only a Running component can stop");
  ASSERT_TRUE(h.configure());
  r = h.stop();
  EXPECT_CONTAINS(r.message, "it is Stopped");
  EXPECT_EQ(h.state(), State::Stopped);
}

TEST(Lifecycle, StartWhenRunningIsRefused) {
  Hooked h;
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.start());
  const Result r = h.start();
  EXPECT_CONTAINS(r.message, "already running");
  EXPECT_EQ(h.state(), State::Running);
  ASSERT_TRUE(h.stop());
}

TEST(Lifecycle, CleanupWhenRunningOrUnconfiguredIsRefused) {
  Hooked h;
  Result r = h.cleanup();
  EXPECT_CONTAINS(r.message, "component 'H': cannot clean up: it is PreOperational");
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.start());
  r = h.cleanup();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "cannot clean up: it is Running; stop it first");
  EXPECT_EQ(h.state(), State::Running);
  EXPECT_CONTAINS(h.configure().message, "cannot configure: it is Running; stop it first");
  EXPECT_EQ(h.state(), State::Running);
  ASSERT_TRUE(h.stop());
  EXPECT_EQ(h.calls, (std::vector<std::string>{"configure", "start", "stop"}));
}

TEST(Lifecycle, RecoverWhenNotInExceptionIsRefused) {
  Hooked h;
  for (auto setup : {std::function<void()>([] {}), std::function<void()>([&] { (void)h.configure(); }),
                     std::function<void()>([&] { (void)h.start(); })}) {
    setup();
    const State before = h.state();
    const Result r = h.recover();
    EXPECT_FALSE(r);
    EXPECT_CONTAINS(r.message, "cannot recover: it is " + std::string(toString(before)));
    EXPECT_CONTAINS(r.message, "only a component in Exception can recover");
    EXPECT_EQ(h.state(), before);
  }
  ASSERT_TRUE(h.stop());
}

// --- hooks that refuse ------------------------------------------------------------------------

TEST(Lifecycle, ConfigureHookReturningFalseStaysPreOperational) {
  Hooked h;
  h.configure_ok = false;
  const Result r = h.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "configureHook refused the configuration");
  EXPECT_EQ(h.state(), State::PreOperational);
  EXPECT_EQ(h.lastError(), r.message);
  h.configure_ok = true;
  EXPECT_TRUE(h.configure());
}

TEST(Lifecycle, StartHookReturningFalseStaysStopped) {
  Hooked h;
  h.start_ok = false;
  ASSERT_TRUE(h.configure());
  const Result r = h.start();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "startHook refused to start");
  EXPECT_EQ(h.state(), State::Stopped);
  step(h);
  EXPECT_EQ(h.updateCount(), 0U);
}

// --- hooks that throw -------------------------------------------------------------------------

struct ThrowCase {
  Hook hook;
  std::string name;  // of the hook, as in lastError()
  std::function<Result(Hooked&)> trigger;  // brings the component there and calls the failing step
  std::vector<std::string> calls;  // hooks run, in order
};

std::vector<ThrowCase> throwCases() {
  return {
      {Hook::Configure, "configureHook", [](Hooked& h) { return h.configure(); }, {"configure", "exception"}},
      {Hook::Start, "startHook",
       [](Hooked& h) {
         (void)h.configure();
         return h.start();
       },
       {"configure", "start", "exception"}},
      {Hook::Update, "updateHook",
       [](Hooked& h) {
         (void)h.configure();
         (void)h.start();
         step(h);
         return h.stop();  // refused: the update already moved it to Exception
       },
       {"configure", "start", "update", "stop", "exception"}},
      {Hook::Stop, "stopHook",
       [](Hooked& h) {
         (void)h.configure();
         (void)h.start();
         return h.stop();
       },
       {"configure", "start", "stop", "exception"}},
      {Hook::Cleanup, "cleanupHook",
       [](Hooked& h) {
         (void)h.configure();
         return h.cleanup();
       },
       {"configure", "cleanup", "exception"}},
  };
}

TEST(Lifecycle, AnExceptionFromEachHookMovesToExceptionAndEmitsAnEvent) {
  for (const ThrowCase& c : throwCases()) {
    SCOPED_TRACE(c.name);
    Hooked h("Probe");
    EventWatch watch(h);
    h.throw_in = c.hook;
    const Result r = c.trigger(h);
    EXPECT_FALSE(r);
    EXPECT_EQ(h.state(), State::Exception);
    EXPECT_EQ(h.calls, c.calls);
    EXPECT_CONTAINS(h.lastError(), "component 'Probe'");
    EXPECT_CONTAINS(h.lastError(), c.name + " threw");
    EXPECT_CONTAINS(h.lastError(), "exploded");
    if (c.hook != Hook::Update) {  // there the failing call is the refused stop() after it
      EXPECT_EQ(r.message, h.lastError());
    }
    const std::vector<Event> events = watch.drain();
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].name, "e_exception@Probe");
    EXPECT_EQ(events[0].source, "Probe");
    // Everything but recover is refused in Exception, and changes nothing.
    EXPECT_CONTAINS(h.configure().message, "cannot configure: it is Exception; recover it first");
    EXPECT_CONTAINS(h.start().message, "cannot start: it is Exception");
    EXPECT_FALSE(h.stop());
    EXPECT_FALSE(h.cleanup());
    EXPECT_EQ(h.state(), State::Exception);
  }
}

TEST(Lifecycle, RecoverThenConfigureAndStartWorkAgain) {
  for (const ThrowCase& c : throwCases()) {
    SCOPED_TRACE(c.name);
    Hooked h;
    h.throw_in = c.hook;
    (void)c.trigger(h);
    ASSERT_EQ(h.state(), State::Exception);
    h.throw_in = Hook::None;
    h.calls.clear();
    ASSERT_TRUE(h.recover());
    EXPECT_EQ(h.state(), State::PreOperational);
    ASSERT_TRUE(h.configure());
    ASSERT_TRUE(h.start());
    step(h);
    EXPECT_EQ(h.state(), State::Running);
    ASSERT_TRUE(h.stop());
    EXPECT_EQ(h.calls, (std::vector<std::string>{"cleanup", "configure", "start", "update", "stop"}));
  }
}

TEST(Lifecycle, ExceptionHookThrowingGivesFatalError) {
  Hooked h("Probe");
  EventWatch watch(h);
  h.throw_in = Hook::Update;
  h.also_throw_in = Hook::Exception;
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.start());
  step(h);
  EXPECT_EQ(h.state(), State::FatalError);
  EXPECT_CONTAINS(h.lastError(), "component 'Probe'");
  EXPECT_CONTAINS(h.lastError(), "exceptionHook threw");
  EXPECT_CONTAINS(h.lastError(), "exception exploded");
  EXPECT_CONTAINS(h.lastError(), "updateHook threw: update exploded");
  const std::vector<Event> events = watch.drain();
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].name, "e_exception@Probe");
  EXPECT_EQ(events[1].name, "e_fatal_error@Probe");
  EXPECT_EQ(events[1].source, "Probe");
  // FatalError is final.
  for (const Result& r : {h.recover(), h.configure(), h.start()}) {
    EXPECT_FALSE(r);
    EXPECT_CONTAINS(r.message, "it is FatalError");
  }
  EXPECT_CONTAINS(h.configure().message, "cannot be used again");
  EXPECT_EQ(h.state(), State::FatalError);
}

TEST(Lifecycle, StopHookThrowingWhileHandlingAnUpdateExceptionGivesFatalError) {
  Hooked h;
  h.throw_in = Hook::Update;
  h.also_throw_in = Hook::Stop;
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.start());
  step(h);
  EXPECT_EQ(h.state(), State::FatalError);
  EXPECT_CONTAINS(h.lastError(), "stopHook threw");
}

TEST(Lifecycle, CleanupHookThrowingDuringRecoverGivesFatalError) {
  Hooked h("Probe");
  h.throw_in = Hook::Start;
  ASSERT_TRUE(h.configure());
  ASSERT_FALSE(h.start());
  ASSERT_EQ(h.state(), State::Exception);
  EventWatch watch(h);
  h.throw_in = Hook::Cleanup;
  const Result r = h.recover();
  EXPECT_FALSE(r);
  EXPECT_EQ(h.state(), State::FatalError);
  EXPECT_CONTAINS(r.message, "component 'Probe': cleanupHook threw during recover: cleanup exploded");
  const std::vector<Event> events = watch.drain();
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].name, "e_fatal_error@Probe");
}

TEST(Lifecycle, NonStandardExceptionsAreCaughtToo) {
  class Odd : public Component {
   public:
    Odd() : Component("Odd", Role::Calculation, "") {}

   protected:
    void updateHook() override { throw 42; }
  };
  Odd o;
  ASSERT_TRUE(o.configure());
  ASSERT_TRUE(o.start());
  step(o);
  EXPECT_EQ(o.state(), State::Exception);
  EXPECT_CONTAINS(o.lastError(), "updateHook threw: unknown exception");
}

TEST(Lifecycle, EventStampComesFromTheComponentsClock) {
  Hooked h;
  EventWatch watch(h);
  h.throw_in = Hook::Configure;
  const auto before = h.now();
  (void)h.configure();
  const auto after = h.now();
  const std::vector<Event> events = watch.drain();
  ASSERT_EQ(events.size(), 1U);
  EXPECT_GE(events[0].stamp, before);
  EXPECT_LE(events[0].stamp, after);
}

TEST(Lifecycle, EmitEventWritesOnTheEventsPort) {
  Hooked h("Planner");
  EventWatch watch(h);
  h.emitEvent("e_plan_done");
  const std::vector<Event> events = watch.drain();
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].name, "e_plan_done");
  EXPECT_EQ(events[0].source, "Planner");
  EXPECT_EQ(h.events().type().kind, DataKind::Logic);
}

// --- names ------------------------------------------------------------------------------------

TEST(Lifecycle, ComponentNamesAreValidated) {
  auto message = [](const std::string& name) {
    try {
      Hooked h(name);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_CONTAINS(message(""), "a component needs a non-empty name");
  EXPECT_CONTAINS(message("arm.left"), "component name 'arm.left' may not contain '.' or spaces");
  EXPECT_CONTAINS(message("arm left"), "may not contain");
  EXPECT_CONTAINS(message("arm\tleft"), "may not contain");
  EXPECT_EQ(message("arm_left-2"), "(accepted)");
}

TEST(Lifecycle, PortPropertyNamesAndDuplicatesAreValidated) {
  EXPECT_THROW((InputPort<double>{"a.b", "", "m"}), Error);
  EXPECT_THROW((InputPort<double>{"", "", "m"}), Error);
  class Dup : public Component {
   public:
    Dup() : Component("Dup", Role::Calculation, "") {
      addPort(in);
      port_msg = capture([this] { addPort(in2); });
      events_msg = capture([this] { addPort(events2); });
      addProperty(p);
      property_msg = capture([this] { addProperty(p2); });
      event_msg = capture([this] { addEventPort(out); });
    }
    static std::string capture(const std::function<void()>& f) {
      try {
        f();
      } catch (const Error& e) {
        return e.what();
      }
      return "(accepted)";
    }
    InputPort<double> in{"in", "", "m"};
    InputPort<int> in2{"in", "", "1"};
    OutputPort<double> events2{"events", "", ""};
    OutputPort<double> out{"out", "", "m"};
    Property<double> p{"p", 0.0, "1", ""};
    Property<int> p2{"p", 0, "1", ""};
    std::string port_msg, events_msg, property_msg, event_msg;
  };
  Dup d;
  EXPECT_CONTAINS(d.port_msg, "component 'Dup' already has a port named 'in'");
  EXPECT_CONTAINS(d.events_msg, "already has a port named 'events'");
  EXPECT_CONTAINS(d.property_msg, "component 'Dup' already has a property named 'p'");
  EXPECT_CONTAINS(d.event_msg, "port 'out' is an output; only inputs can be event ports");
  try {
    InputPort<double> bad{"a b", "", "m"};
    FAIL();
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "port name 'a b' must be non-empty without '.' or spaces");
  }
}

TEST(Lifecycle, SetActivityIsRefusedWhileRunningOrEmpty) {
  Hooked h;
  EXPECT_CONTAINS(
      [&] {
        try {
          h.setActivity(nullptr);
        } catch (const Error& e) {
          return std::string(e.what());
        }
        return std::string();
      }(),
      "setActivity needs an activity");
  ASSERT_TRUE(h.configure());
  ASSERT_TRUE(h.start());
  try {
    h.setActivity(std::make_unique<SlaveActivity>());
    FAIL();
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "component 'H': cannot change the activity while it is Running; stop it first");
  }
  ASSERT_TRUE(h.stop());
  h.setActivity(std::make_unique<SlaveActivity>());
  EXPECT_EQ(h.activity().describe(), "slave");
}

class Picky : public Component {
 public:
  explicit Picky(std::string name) : Component(std::move(name), Role::Bridge, "refuses with reasons") {}
  bool allow_configure = false;
  bool allow_start = false;

 protected:
  bool configureHook() override { return allow_configure || refuse("cannot open /dev/ttyS9: no such device"); }
  bool startHook() override { return allow_start || refuse("the drive is not powered; switch it on"); }
};

TEST(Lifecycle, AHookRefusesWithItsReasonAndTheComponentStaysWhereItWas) {
  Picky p("Drive");
  Result r = p.configure();
  EXPECT_FALSE(r);
  EXPECT_EQ(r.message, "component 'Drive': cannot open /dev/ttyS9: no such device");
  EXPECT_EQ(p.state(), State::PreOperational);
  EXPECT_EQ(p.lastError(), r.message);
  p.allow_configure = true;
  ASSERT_TRUE(p.configure());
  r = p.start();
  EXPECT_EQ(r.message, "component 'Drive': the drive is not powered; switch it on");
  EXPECT_EQ(p.state(), State::Stopped);
  p.allow_start = true;
  EXPECT_TRUE(p.start());
}

/// Makes one output per `count` at configure time, as a multi-arm component does.
class Arms : public Component {
 public:
  explicit Arms(std::string name) : Component(std::move(name), Role::Calculation, "ports made at configure time") {
    addProperty(count_);
  }
  using Component::removePort;  // public here, to test its refusals
  std::vector<std::unique_ptr<OutputPort<double>>> outputs;

 protected:
  bool configureHook() override {
    for (auto& p : outputs) removePort(*p);
    outputs.clear();
    for (int i = 1; i <= count_(); ++i) {
      outputs.push_back(std::make_unique<OutputPort<double>>("out_" + std::to_string(i), "arm output", "m"));
      addPort(*outputs.back());
    }
    return true;
  }

 private:
  Property<int> count_{"count", 2, "1", "number of outputs"};
};

TEST(ComponentPorts, PortsMadeAtConfigureTimeCanBeRemovedAndTheirConnectionsGo) {
  Arms arms("Arms");
  ASSERT_TRUE(arms.configure());
  EXPECT_NE(arms.findPort("out_2"), nullptr);
  InputPort<double> reader{"in", "reader", "m"};
  connectPorts(arms.port("out_2"), reader);
  arms.setProperty("count", 1);
  ASSERT_TRUE(arms.configure());
  EXPECT_EQ(arms.findPort("out_2"), nullptr);
  EXPECT_NE(arms.findPort("out_1"), nullptr);
  EXPECT_FALSE(reader.connected());
  ASSERT_TRUE(arms.start());
  OutputPort<double> stray{"stray", "not a port of Arms", "m"};
  EXPECT_EQ(messageOf([&] { arms.removePort(*arms.outputs[0]); }),
            "component 'Arms' is Running: stop it before removing port 'out_1'");
  ASSERT_TRUE(arms.stop());
  EXPECT_EQ(messageOf([&] { arms.removePort(stray); }), "component 'Arms' has no port 'stray' to remove");
}

}  // namespace
}  // namespace cobra::core
