// CryoConsole: one freeze cycle per request, on the lockstep clock: alone against a scripted
// iceball (timing, ignored requests, refusals, no allocation), then wired to PatientSimulator as
// world.lua wires it (the patient freezes and traps the needle, thaws, and the console reports it).
#include "cobra/components/sim/cryo_console.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "puncturing_world.hpp"

namespace cobra::components::test {
namespace {

/// The console alone at 1 kHz: requests in, a scripted iceball radius in, its events and commands out.
struct Bench {
  core::LockstepClock clock;
  CryoConsole console{"Cryo"};
  core::OutputPort<core::Event> requests{"requests", "", ""};
  core::OutputPort<double> radius{"radius", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<double> command{"command", "", "1"};
  core::InputPort<double> phase{"phase", "", "1"};
  std::vector<std::string> said;  // "<ms> <event>"
  int ms = 0;

  Bench() {
    clock.add(console, std::chrono::milliseconds(1));
    core::connectPorts(requests, console.port("inputEvents"), core::ConnPolicy::buffer(8));
    core::connectPorts(radius, console.port("iceballRadius"));
    core::connectPorts(console.port("events"), events, core::ConnPolicy::buffer(8));
    core::connectPorts(console.port("freezeCommand"), command);
    core::connectPorts(console.port("cyclePhase"), phase);
    console.setProperty("freeze_duration", 2.0);
    console.setProperty("thawed_radius", 0.002);
  }
  void ask(const char* name) {
    core::Event e;
    e.name = name;
    e.source = "NeedleTaskSup";
    requests.write(e);
  }
  /// `steps` ms with the iceball at `r` m.
  void run(int steps, double r) {
    for (int i = 0; i < steps; ++i) {
      radius.write(r);
      clock.advance(std::chrono::milliseconds(1));
      ++ms;
      for (core::Event e; events.read(e) == core::FlowStatus::NewData;) said.push_back(std::to_string(ms) + " " + e.name.str());
    }
  }
  double read(core::InputPort<double>& port) {
    double v = NAN;
    (void)port.read(v);
    return v;
  }
};

TEST(CryoConsole, ARequestFreezesForTheFreezeDurationThenReportsTheThawAtTheThawedRadius) {
  Bench b;
  ASSERT_TRUE(b.console.configure());
  ASSERT_TRUE(b.console.start());
  b.run(100, 0.0);
  EXPECT_TRUE(std::isnan(b.read(b.command)));  // nothing asked, nothing commanded
  EXPECT_EQ(b.read(b.phase), 0.0);

  b.ask("e_needle_placed");  // not a request of the console
  b.run(100, 0.0);
  EXPECT_TRUE(std::isnan(b.read(b.command)));

  b.ask("e_cryo_start");  // at 200 ms
  b.run(1, 0.0);
  EXPECT_EQ(b.read(b.command), 1.0);
  EXPECT_EQ(b.read(b.phase), 1.0);
  b.run(1998, 0.01);  // frozen; an iceball at or below the thawed radius does not end a freeze
  b.run(1, 0.001);
  EXPECT_EQ(b.read(b.phase), 1.0);
  EXPECT_TRUE(b.said.empty());
  b.run(1, 0.01);  // 2 s after the request: the thaw
  EXPECT_EQ(b.read(b.command), 0.0);
  EXPECT_EQ(b.read(b.phase), 2.0);
  b.run(500, 0.005);  // still thawing above the thawed radius
  EXPECT_TRUE(b.said.empty());
  b.run(1, 0.0021);
  EXPECT_TRUE(b.said.empty());
  b.run(1, 0.002);
  EXPECT_EQ(b.said, (std::vector<std::string>{"2703 e_cryo_done"}));
  EXPECT_EQ(b.read(b.phase), 0.0);
  b.run(1000, 0.0);
  EXPECT_EQ(b.said.size(), 1u);  // once per cycle
}

TEST(CryoConsole, ARequestDuringACycleIsIgnoredAndTheNextCycleStartsAfterTheReport) {
  Bench b;
  b.console.setProperty("start_event", "e_freeze");
  b.console.setProperty("done_event", "e_thawed");
  ASSERT_TRUE(b.console.configure());
  ASSERT_TRUE(b.console.start());
  b.ask("e_freeze");
  b.run(1000, 0.01);
  b.ask("e_freeze");  // one cycle at a time: its freeze still ends 2 s after the first request
  b.run(1000, 0.01);
  EXPECT_EQ(b.read(b.command), 1.0);
  b.run(1, 0.01);
  EXPECT_EQ(b.read(b.command), 0.0);
  b.run(10, 0.0);
  EXPECT_EQ(b.said, (std::vector<std::string>{"2002 e_thawed"}));
  b.ask("e_freeze");
  b.run(1, 0.0);
  EXPECT_EQ(b.read(b.command), 1.0);
  b.run(2010, 0.0);
  EXPECT_EQ(b.said, (std::vector<std::string>{"2002 e_thawed", "4012 e_thawed"}));
}

TEST(CryoConsole, RequestsSentBeforeTheStartAreDropped) {
  Bench b;
  ASSERT_TRUE(b.console.configure());
  b.ask("e_cryo_start");
  ASSERT_TRUE(b.console.start());
  b.run(3000, 0.0);
  EXPECT_TRUE(std::isnan(b.read(b.command)));
  EXPECT_TRUE(b.said.empty());
}

TEST(CryoConsole, BadPropertiesAndAMissingThawSensorAreRefusedByName) {
  {
    CryoConsole c("Cryo");
    c.setProperty("freeze_duration", 0.0);
    const core::Result r = c.configure();
    EXPECT_FALSE(r);
    EXPECT_CONTAINS(r.message, "component 'Cryo': property freeze_duration is 0.000000 s; expected > 0 s");
  }
  {
    CryoConsole c("Cryo");
    c.setProperty("thawed_radius", -0.001);
    EXPECT_CONTAINS(c.configure().message, "property thawed_radius is -0.001000 m; expected >= 0 m");
  }
  {
    CryoConsole c("Cryo");
    c.setProperty("done_event", "");
    EXPECT_CONTAINS(c.configure().message, "property done_event is ''; expected an event name of 1 to 63 characters");
  }
  {
    CryoConsole c("Cryo");
    ASSERT_TRUE(c.configure());
    const core::Result r = c.start();
    EXPECT_FALSE(r);
    EXPECT_CONTAINS(r.message, "component 'Cryo': input port iceballRadius is not connected");
    EXPECT_EQ(c.state(), core::State::Stopped);
  }
}

TEST(CryoConsole, AWholeCycleAllocatesNothing) {
  Bench b;
  ASSERT_TRUE(b.console.configure());
  ASSERT_TRUE(b.console.start());
  b.run(10, 0.0);
  b.said.reserve(8);
  core::Event request;
  request.name = "e_cryo_start";
  const long allocations = test_support::allocationsDuring([&] {
    b.requests.write(request);
    for (int i = 0; i < 3000; ++i) {
      b.radius.write(i < 2500 ? 0.01 : 0.0);
      b.clock.advance(std::chrono::milliseconds(1));
    }
  });
  EXPECT_EQ(allocations, 0);
  core::Event done;
  ASSERT_EQ(b.events.read(done), core::FlowStatus::NewData);
  EXPECT_EQ(done.name, "e_cryo_done");
}

TEST(CryoConsole, WiredToThePatientItFreezesTheIceballAroundTheNeedleAndReportsItsThaw) {
  PuncturingWorld world;
  world.patient.setProperty("freeze_time_constant", 0.5);  // s: a fast iceball
  world.patient.setProperty("thaw_time_constant", 0.3);    // s
  CryoConsole console("Cryo");
  console.setProperty("freeze_duration", 1.0);
  console.setProperty("thawed_radius", 0.001);
  world.clock.add(console, std::chrono::milliseconds(1));
  core::OutputPort<core::Event> requests{"requests", "", ""};
  core::InputPort<double> radius{"radius", "", "m"};
  core::connectPorts(requests, console.port("inputEvents"), core::ConnPolicy::buffer(8));
  core::connectPorts(console.port("freezeCommand"), world.patient.port("freezeCommand"));
  core::connectPorts(world.patient.port("iceballRadius"), console.port("iceballRadius"));
  core::connectPorts(world.patient.port("iceballRadius"), radius);
  core::connectPorts(console.port("events"), world.events, core::ConnPolicy::buffer(64));
  ASSERT_EQ(world.start(), "");
  ASSERT_TRUE(console.configure());
  ASSERT_TRUE(console.start());

  for (int ms = 0; ms < 3000; ++ms) world.step(0.005 * ms * 1e-3);  // 15 mm along the needle, into the fat
  (void)world.takeEvents();
  core::Event start;
  start.name = "e_cryo_start";
  requests.write(start);
  double biggest = 0.0;
  int done_at = -1;
  for (int ms = 0; ms < 3000 && done_at < 0; ++ms) {
    world.step(0.015);
    biggest = std::max(biggest, world.read(radius));
    for (const std::string& e : world.takeEvents())
      if (e == "e_cryo_done") done_at = ms;
  }
  // 1 s of freezing with a 0.5 s time constant: 1 - e^-2 of the 15 mm plateau; then a thaw
  // with 0.3 s to 1 mm: 0.3 ln(12.97) = 0.77 s.
  EXPECT_NEAR(biggest, 0.015 * (1.0 - std::exp(-2.0)), 2e-4);
  EXPECT_NEAR(done_at, 1000 + 769, 5);
  EXPECT_LE(world.read(radius), 0.001);
}

}  // namespace
}  // namespace cobra::components::test
