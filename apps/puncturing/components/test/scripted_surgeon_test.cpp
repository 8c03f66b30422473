// The scripted surgeon on the lockstep clock: timed and state-triggered events, `times`, say().
#include "cobra/components/puncturing/scripted_surgeon.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

/// Writes `text` to a file in the test's temporary folder and returns its path.
std::string writeFile(const std::string& name, const std::string& text) {
  const auto dir = ::cobra::test_support::scratchPath("cobra_scripted_surgeon_test");
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

constexpr const char* kScript =
    "# test surgeon\n"
    "at 1 e_iceball_configured\n"
    "on needle.WaitNeedleMounted e_needle_mounted after=5\n"
    "on needle.WaitReaction e_recover after=3 times=1\n"
    "on needle.WaitReaction e_take_over after=1\n"
    "on us.WaitReaction e_recover after=0.5\n"
    "on needle.MoveToSkin e_teleop_done after=0.25 times=2\n";

/// A surgeon on a 10 ms lockstep clock; the two charts' taskState ports are test ports.
struct Bench {
  ScriptedSurgeon surgeon{"Surgeon"};
  core::LockstepClock clock;
  core::OutputPort<core::TaskState> needle{"needleState", "test needle chart", ""};
  core::OutputPort<core::TaskState> us{"usState", "test us chart", ""};
  core::InputPort<core::Event> events{"events", "test supervisor", ""};

  explicit Bench(const std::string& script = writeFile("surgeon.txt", kScript)) {
    surgeon.setProperty("script_file", script);
    clock.add(surgeon, 10ms);
    core::connectPorts(surgeon.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(needle, surgeon.port("needleTaskState"), core::ConnPolicy::buffer(16));
    core::connectPorts(us, surgeon.port("usTaskState"), core::ConnPolicy::buffer(16));
  }
  /// "event@seconds" of the events emitted since the last call.
  std::vector<std::string> take() {
    std::vector<std::string> out;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) {
      char stamp[32];
      std::snprintf(stamp, sizeof stamp, "@%.2f", std::chrono::duration<double>(e.stamp).count());
      out.push_back(e.name.str() + stamp);
    }
    return out;
  }
  void enter(core::OutputPort<core::TaskState>& chart, const char* path) { chart.write(core::TaskState{path}); }
};

TEST(ScriptedSurgeon, FiresATimedEventOnceAtItsTime) {
  Bench b;
  ASSERT_TRUE(b.surgeon.configure()) << b.surgeon.lastError();
  ASSERT_TRUE(b.surgeon.start()) << b.surgeon.lastError();
  b.clock.advance(990ms);
  EXPECT_EQ(b.take(), std::vector<std::string>{});
  b.clock.advance(20ms);
  EXPECT_EQ(b.take(), std::vector<std::string>{"e_iceball_configured@1.00"});
  b.clock.advance(5s);
  EXPECT_EQ(b.take(), std::vector<std::string>{});
}

TEST(ScriptedSurgeon, FiresAStateTriggeredEventItsDelayAfterTheStateIsEntered) {
  Bench b;
  ASSERT_TRUE(b.surgeon.configure());
  ASSERT_TRUE(b.surgeon.start());
  b.clock.advance(2s);
  b.take();
  b.enter(b.needle, "root.InsertingNeedles.WaitNeedleMounted");  // seen at the step of t = 2 s
  b.clock.advance(4990ms);
  EXPECT_EQ(b.take(), std::vector<std::string>{});
  b.clock.advance(20ms);
  EXPECT_EQ(b.take(), std::vector<std::string>{"e_needle_mounted@7.00"});
  // The same state published again is no new entry; leaving and entering again is.
  b.enter(b.needle, "root.InsertingNeedles.WaitNeedleMounted");
  b.clock.advance(6s);
  EXPECT_EQ(b.take(), std::vector<std::string>{});
  b.enter(b.needle, "root.InsertingNeedles.MoveToNeedleChange.Moving");
  b.enter(b.needle, "root.InsertingNeedles.WaitNeedleMounted");  // both in one step: buffered, both seen
  b.clock.advance(6s);
  EXPECT_EQ(b.take(), std::vector<std::string>{"e_needle_mounted@18.01"});
  // The other chart's states do not trigger the needle lines.
  b.enter(b.us, "root.WaitNeedleMounted");
  b.clock.advance(6s);
  EXPECT_EQ(b.take(), std::vector<std::string>{});
}

TEST(ScriptedSurgeon, TimesUsesALineUpThenTheNextLineForTheStateFires) {
  Bench b;
  ASSERT_TRUE(b.surgeon.configure());
  ASSERT_TRUE(b.surgeon.start());
  b.clock.advance(2s);
  b.take();
  const char* reaction = "root.WaitReaction";
  const char* moving = "root.InsertingNeedles.MoveToTumor.Moving";
  b.enter(b.needle, reaction);  // t = 2: e_recover (times=1) 3 s later
  b.clock.advance(4s);
  b.enter(b.needle, moving);
  b.enter(b.needle, reaction);  // t = 6: that line is used up: e_take_over 1 s later
  b.clock.advance(2s);
  b.enter(b.needle, moving);
  b.enter(b.needle, reaction);  // t = 8: e_take_over again (no limit)
  b.enter(b.us, "root.WaitReaction");  // the us chart's own line
  b.clock.advance(2s);
  EXPECT_EQ(b.take(), (std::vector<std::string>{"e_recover@5.00", "e_take_over@7.00", "e_recover@8.50",
                                                "e_take_over@9.00"}));
}

TEST(ScriptedSurgeon, ACompositeStateIsEnteredOnceWhileItsLeavesChange) {
  Bench b;
  ASSERT_TRUE(b.surgeon.configure());
  ASSERT_TRUE(b.surgeon.start());
  b.clock.advance(2s);
  b.take();
  for (int entry = 0; entry < 3; ++entry) {  // times=2: the third entry fires nothing
    for (const char* leaf : {"root.InsertingNeedles.MoveToSkin.Approach.Switching",
                             "root.InsertingNeedles.MoveToSkin.Approach.AskingGoal",
                             "root.InsertingNeedles.MoveToSkin.Descend.Moving"}) {
      b.enter(b.needle, leaf);
      b.clock.advance(100ms);
    }
    b.enter(b.needle, "root.InsertingNeedles.PenetratingSkin.Moving");
    b.clock.advance(700ms);
  }
  EXPECT_EQ(b.take(), (std::vector<std::string>{"e_teleop_done@2.25", "e_teleop_done@3.25"}));
}

TEST(ScriptedSurgeon, SayEmitsASurgeonEventAndRejectsOthersNamingTheAllowedOnes) {
  Bench b;
  ASSERT_TRUE(b.surgeon.configure());
  ASSERT_TRUE(b.surgeon.start());
  b.clock.advance(300ms);
  b.surgeon.call<void>("say", std::string("e_take_over"));
  EXPECT_EQ(b.take(), std::vector<std::string>{"e_take_over@0.30"});
  try {
    b.surgeon.call<void>("say", std::string("e_open_door"));
    FAIL() << "say accepted e_open_door";
  } catch (const core::Error& e) {
    EXPECT_CONTAINS(e.what(), "'e_open_door' is not a surgeon event; say one of: e_iceball_configured, "
                              "e_needle_mounted, e_needle_removed, e_cryo_done, e_recover, e_take_over, e_teleop_done");
  }
  EXPECT_EQ(b.take(), std::vector<std::string>{});
}

TEST(ScriptedSurgeon, RefusesABadScriptNamingFileAndLineAndNeedsAPeriod) {
  {
    Bench b(writeFile("bad_surgeon.txt", "at 1 e_iceball_configured\non heart.Beat e_recover\n"));
    EXPECT_FALSE(b.surgeon.configure());
    EXPECT_CONTAINS(b.surgeon.lastError(), "component 'Surgeon'");
    EXPECT_CONTAINS(b.surgeon.lastError(), "bad_surgeon.txt:2: chart 'heart' is neither needle nor us");
  }
  {
    ScriptedSurgeon s("Surgeon");
    EXPECT_FALSE(s.configure());
    EXPECT_CONTAINS(s.lastError(), "property script_file is empty");
    s.setProperty("script_file", std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles/surgeon.txt");
    ASSERT_TRUE(s.configure()) << s.lastError();
    EXPECT_EQ(s.script().actions.size(), 7u);  // the cryo cycle is the CryoConsole's, not a surgeon line
    core::LockstepClock clock;
    clock.add(s, 0ms);
    EXPECT_FALSE(s.start());
    EXPECT_CONTAINS(s.lastError(), "needs a periodic activity");
  }
}

TEST(ScriptedSurgeon, UpdateAllocatesNothing) {
  Bench b;
  ASSERT_TRUE(b.surgeon.configure());
  ASSERT_TRUE(b.surgeon.start());
  b.clock.advance(10ms);
  const long allocations = test_support::allocationsDuring([&] {
    for (int i = 0; i < 20; ++i) {
      b.enter(b.needle, i % 2 ? "root.WaitReaction" : "root.InsertingNeedles.WaitNeedleMounted");
      b.enter(b.us, i % 2 ? "root.WaitReaction" : "root.MoveToSkin.Approach.Moving");
      b.clock.advance(500ms);
    }
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(b.take().size(), 15u);  // the events of that loop did fire
}

}  // namespace
}  // namespace cobra::components
