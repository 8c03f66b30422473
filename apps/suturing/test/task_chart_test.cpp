// The suturing chart (charts/suturing.lua, thesis Fig. 5.11) loaded by cobra's rFSM loader and run
// on the statechart engine, its peers fakes that record the operations called and answer as the
// real components do: the deployment and configuration supervisors, the StitchPlanner (a plan of
// N stitches), the Frame Generator, the planner, the trajectory generator, the robot's Endo Stitch
// (e_actuate_endo_stitch answered after its 0.3 s actuation), the RestMonitor (the tools at rest
// 0.3 s after the ask). Faults are played into it: the
// surgeon taking over mid-stitch, a planner failure (once: recovered; twice: safe stop; never
// answered: safe stop after the reaction timeout), the thread breaking, a sensing module without
// edges at first, tools that never come to rest at the end.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <sstream>

#include "cobra/script/rfsm.hpp"
#include "cobra/statechart/machine.hpp"
#include "cobra/test_support/chart_fakes.hpp"

namespace cobra::suturing {
namespace {

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/suturing/";
constexpr double kActuation = 0.3;  // s: the Endo Stitch's actuation_time

// Fake peers in Lua (test_support/chart_fakes.hpp).
const std::string kFakes =
    test_support::fakePeersLua({"SutureFrames", "SuturePlanner", "SutureTrajGen", "Stitches", "RightTransparency",
                                "LeftTransparency", "ArmsRest"});
using Entered = test_support::EntryLogger;

/// The chart, its fake peers and world, on a clock in 10 ms ticks.
class Procedure {
 public:
  explicit Procedure(int stitches) : stitches_(stitches) {
    lua_.run(kFakes, "=fakes");
    // As the Supervisor does: the chart's folder heads package.path, then cobra's charts (task_steps.lua).
    lua_.run("package.path = '" + kApp + "charts/?.lua;" COBRA_CHARTS_DIR "/?.lua;' .. package.path", "=charts path");
    chart_ = script::RfsmChart::loadFile(lua_, kApp + "charts/suturing.lua");
    machine_ = std::make_unique<statechart::Machine>(
        chart_->chart(), [this] { return std::chrono::nanoseconds(static_cast<long long>(now_ * 1e9)); });
    chart_->bind(machine_.get());
    observer_.lua = &lua_;
    machine_->setObserver(&observer_);
  }

  /// Event `event` ends the next `times` motions of state `fqn` instead of e_motion_done.
  void fault(const std::string& fqn, const std::string& event, int times = 1) { faults_[fqn] = {event, times}; }
  /// `event` comes `delay` s after the chart first enters `state`.
  void onEntry(const std::string& state, const std::string& event, double delay) {
    triggers_.push_back({state, event, delay, false});
  }
  void failPlans(int times) { fail_plans_ = times; }
  void noEdgesFirst(int times) { no_edges_ = times; }
  /// The RestMonitor never answers: the tools keep moving.
  void neverAtRest() { never_at_rest_ = true; }

  void run(double limit = 600.0) {
    step();
    while (now_ < limit && !ended()) {
      now_ += 0.01;
      std::stable_sort(pending_.begin(), pending_.end(), [](const auto& a, const auto& b) { return a.at < b.at; });
      while (!pending_.empty() && pending_.front().at <= now_ + 1e-9) {
        const Pending p = pending_.front();
        pending_.erase(pending_.begin());
        if (p.motion != 0 && p.motion != motion_) continue;  // answers a motion that was stopped
        timeline_.push_back("<- " + p.event);
        machine_->raise(p.event);
      }
      step();
    }
  }

  bool ended() const { return leaf() == "root.Done" || leaf() == "root.SafeStop"; }
  std::string leaf() const { return std::string(machine_->activeLeaf()); }
  double now() const { return now_; }
  const std::vector<std::string>& timeline() const { return timeline_; }
  std::size_t count(const std::string& line) const {
    return static_cast<std::size_t>(std::count(timeline_.begin(), timeline_.end(), line));
  }
  std::size_t find(const std::string& line, std::size_t from = 0) const {
    for (std::size_t i = from; i < timeline_.size(); ++i)
      if (timeline_[i] == line) return i;
    return std::string::npos;
  }
  /// The states entered, motions folded to their state (Switching, AskingGoal, ... left out).
  std::vector<std::string> states() const {
    std::vector<std::string> out;
    for (const std::string& line : timeline_) {
      if (!line.starts_with("> ")) continue;
      const std::string fqn = line.substr(2);
      const std::string last = fqn.substr(fqn.rfind('.') + 1);
      if (last == "Switching" || last == "AskingGoal" || last == "Planning" || last == "Generating" ||
          last == "Moving" || last == "Arrived")
        continue;
      out.push_back(fqn);
    }
    return out;
  }
  /// The configuration asked last before each entry of `state` (a motion's Switching).
  std::vector<std::string> configurationsOf(const std::string& state) const {
    std::vector<std::string> out;
    std::string configuration;
    for (const std::string& line : timeline_) {
      if (line.starts_with(": emit:e_configure_")) configuration = line.substr(19);
      if (line == "> " + state + ".AskingGoal") out.push_back(configuration);
    }
    return out;
  }

 private:
  struct Pending {
    double at;
    std::string event;
    int motion;
  };
  struct Trigger {
    std::string state, event;
    double delay;
    bool fired;
  };

  void at(double t, const std::string& event, int motion = 0) { pending_.push_back({t, event, motion}); }

  void step() {
    for (bool busy = true; busy;) {
      busy = false;
      machine_->run();
      std::istringstream lines(lua_.evaluate("drain()"));
      for (std::string line; std::getline(lines, line);) {
        busy = true;
        if (line.starts_with("enter:")) {
          timeline_.push_back("> " + line.substr(6));
          for (Trigger& t : triggers_) {
            if (!t.fired && line.substr(6) == t.state) {
              t.fired = true;
              at(now_ + t.delay, t.event);
            }
          }
        } else {
          answer(line);
        }
      }
    }
  }

  void answer(const std::string& line) {
    timeline_.push_back(": " + line);
    const std::string leaf = this->leaf();
    const std::string motion_fqn = leaf.substr(0, leaf.rfind('.'));
    auto reply = [&](const std::string& event, double delay = 0.02, int motion = 0) { at(now_ + delay, event, motion); };
    if (line.starts_with("emit:e_deploy_")) {
      deployment_ = line.substr(14);
      reply("e_deployed_" + deployment_);
    } else if (line.starts_with("emit:e_configure_")) {
      reply("e_configured_" + line.substr(17));
    } else if (line == "emit:e_actuate_endo_stitch") {
      reply("e_endo_stitch_actuated", kActuation);  // the robot's Endo Stitch
    } else if (line == "Stitches:askStitch") {
      if (no_edges_ > 0) {
        --no_edges_;
        reply("e_no_wound_data");
      } else {
        reply(stitch_ < stitches_ ? "e_stitch_planned" : "e_stitches_done");
      }
    } else if (line == "ArmsRest:askAtRest") {
      if (!never_at_rest_) reply("e_at_rest", 0.3);
    } else if (line == "Stitches:nextStitch") {
      ++stitch_;
    } else if (line == "SutureFrames:askCurrentGoal") {
      reply("e_goal_ready");
      if (deployment_ == "suturing_autonomous_primitives") reply("e_path_ready", 0.03);  // desiredPoses is the path
    } else if (line == "SuturePlanner:askPlan") {
      if (fail_plans_ > 0) {
        --fail_plans_;
        reply("e_plan_failed", 0.5);
      } else {
        reply("e_plan_done", 0.5);
        reply("e_path_ready", 0.51);
      }
    } else if (line == "SutureTrajGen:askGenerateTraj") {
      reply("e_trajectory_ready");
    } else if (line == "SutureTrajGen:askStartMove") {
      motion_ = ++motions_;
      std::string end = "e_motion_done";
      if (auto f = faults_.find(motion_fqn); f != faults_.end() && f->second.second > 0) {
        --f->second.second;
        end = f->second.first;
      }
      reply(end, 1.0, motion_);
    } else if (line == "SutureTrajGen:askStopMove") {
      if (motion_ == 0) {
        reply("e_not_moving");
      } else {
        motion_ = 0;
        reply("e_motion_stopped", 0.2);
      }
    }
  }

  script::LuaState lua_;
  std::unique_ptr<script::RfsmChart> chart_;
  std::unique_ptr<statechart::Machine> machine_;
  Entered observer_;
  double now_ = 0.0;
  int stitches_, stitch_ = 0;
  int motion_ = 0, motions_ = 0;
  int fail_plans_ = 0, no_edges_ = 0;
  bool never_at_rest_ = false;
  std::string deployment_;
  std::vector<Pending> pending_;
  std::vector<std::string> timeline_;
  std::map<std::string, std::pair<std::string, int>> faults_;
  std::vector<Trigger> triggers_;
};

const std::string kAuto = "root.AutonomousMode.";

/// The states of one stitch, §5.6's phases B-H with the thread handled after each half.
std::vector<std::string> oneStitch() {
  std::vector<std::string> out;
  for (const char* side : {"Right", "Left"}) {
    const std::string half = kAuto + "Apply" + side + "Stitch";
    out.push_back(half);
    for (const char* s : {"MoveOverWound", "MoveInsideWound", "MoveToWoundEdge", "ApplyStitch", "DisengageNeedle"})
      out.push_back(half + "." + s);
    for (const char* s : {"PullThread", "HookThread", "PushThread"}) out.push_back(kAuto + s);
  }
  return out;
}

TEST(SuturingChart, AppliesBothHalvesOfEveryPlannedStitchInThePhasesOrderThenIsDone) {
  Procedure p(4);
  p.run();
  ASSERT_EQ(p.leaf(), "root.Done") << "at " << p.now() << " s";
  std::vector<std::string> expected = {"root", "root.WaitStitchesPlan", "root.AutonomousMode"};
  for (int stitch = 0; stitch < 4; ++stitch) {
    const std::vector<std::string> one = oneStitch();
    expected.insert(expected.end(), one.begin(), one.end());
    expected.push_back(kAuto + "GetStitchTargetPose");
  }
  expected.push_back("root.Finishing");  // the tools come to rest before the procedure is done
  expected.push_back("root.Done");
  EXPECT_EQ(p.states(), expected);
  EXPECT_EQ(p.count(": ArmsRest:askAtRest"), 1u);
  EXPECT_LT(p.find("<- e_stitches_done"), p.find(": ArmsRest:askAtRest"));
  EXPECT_LT(p.find("<- e_at_rest"), p.find(": emit:e_suture_task_done"));
  EXPECT_EQ(p.count(": emit:e_actuate_endo_stitch"), 8u);
  EXPECT_EQ(p.count(": emit:e_half_stitch_right"), 4u);
  EXPECT_EQ(p.count(": emit:e_half_stitch_left"), 4u);
  EXPECT_EQ(p.count(": emit:e_release_thread"), 8u);
  EXPECT_EQ(p.count(": emit:e_stitch_done"), 4u);
  EXPECT_EQ(p.count(": Stitches:nextStitch"), 4u);
  EXPECT_EQ(p.count(": SuturePlanner:askPlan"), 8u);  // MoveOverWound, planned, twice per stitch
  // §5.5.2: the contact configuration only while pulling the thread.
  EXPECT_EQ(p.configurationsOf(kAuto + "PullThread"), std::vector<std::string>(8, "suturing_contact"));
  EXPECT_EQ(p.configurationsOf(kAuto + "HookThread"), std::vector<std::string>(8, "suturing_free_motion"));
  // The half-stitch is reported only once the robot said the Endo Stitch actuated.
  const std::size_t asked = p.find(": emit:e_actuate_endo_stitch");
  EXPECT_LT(asked, p.find("<- e_endo_stitch_actuated", asked));
  EXPECT_LT(p.find("<- e_endo_stitch_actuated", asked), p.find(": emit:e_half_stitch_right", asked));
}

TEST(SuturingChart, ASurgeonTakingOverMidStitchStopsTheMotionThenTeleoperatesAndResumes) {
  Procedure p(2);
  const std::string edge = kAuto + "ApplyRightStitch.MoveToWoundEdge";
  p.onEntry(edge + ".Moving", "e_take_over", 0.5);
  p.onEntry("root.TeleoperatedMode.TeleoperationActive", "e_teleop_done", 5.0);
  p.run();
  ASSERT_EQ(p.leaf(), "root.Done");
  const std::size_t take = p.find("<- e_take_over");
  ASSERT_NE(take, std::string::npos);
  // In this order (an entry's calls are logged before the state's entry itself).
  std::size_t at = take;
  for (const char* line : {": SutureTrajGen:askStopMove", "> root.TeleoperatedMode.StoppingMotion", "<- e_motion_stopped",
                           ": emit:e_deploy_suturing_teleoperated", "> root.TeleoperatedMode.InitHapticDevice",
                           "<- e_deployed_suturing_teleoperated", ": RightTransparency:engage",
                           ": LeftTransparency:engage", "> root.TeleoperatedMode.TeleoperationActive"}) {
    const std::size_t next = p.find(line, at);
    ASSERT_NE(next, std::string::npos) << line;
    at = next;
  }
  const std::size_t active = at;
  EXPECT_EQ(p.count("> root.TeleoperatedMode.StoppingMotion"), 1u);
  EXPECT_EQ(p.count(": RightTransparency:engage"), 1u);  // the couplings engage once per teleoperation
  EXPECT_EQ(p.count(": LeftTransparency:engage"), 1u);
  // The interrupted motion starts again from where the arms are.
  EXPECT_NE(p.find("> " + edge, p.find("<- e_teleop_done", active)), std::string::npos);
  EXPECT_EQ(p.count(": emit:e_actuate_endo_stitch"), 4u);
}

TEST(SuturingChart, APlannerFailureIsAReactionOnceAndASafeStopTwice) {
  {
    Procedure p(1);
    p.failPlans(1);
    p.onEntry("root.WaitReaction", "e_recover", 2.0);
    p.run();
    EXPECT_EQ(p.leaf(), "root.Done");
    const std::size_t reaction = p.find("> root.WaitReaction");
    ASSERT_NE(reaction, std::string::npos);
    EXPECT_NE(p.find("> " + kAuto + "ApplyRightStitch.MoveOverWound", reaction), std::string::npos);
  }
  Procedure p(1);
  p.failPlans(2);
  p.onEntry("root.WaitReaction", "e_recover", 2.0);
  p.run();
  EXPECT_EQ(p.leaf(), "root.SafeStop");
  EXPECT_EQ(p.count(": emit:e_suture_safe_stop"), 1u);
  EXPECT_EQ(p.count(": emit:e_actuate_endo_stitch"), 0u);
}

TEST(SuturingChart, ASurgeonWhoNeverReactsIsASafeStopAfterTheReactionTimeoutNamingIt) {
  Procedure p(1);
  p.failPlans(1);  // a reaction, and nobody answers it
  p.run();
  EXPECT_EQ(p.leaf(), "root.SafeStop");
  const std::size_t reaction = p.find("> root.WaitReaction");
  ASSERT_NE(reaction, std::string::npos);
  const std::size_t timeout = p.find(": emit:e_reaction_timeout", reaction);
  ASSERT_NE(timeout, std::string::npos);
  EXPECT_NE(p.find(": emit:e_suture_safe_stop", timeout), std::string::npos);
  // The chart's reaction_timeout (120 s, simulated) after the failure of the first plan (0.5 s in).
  EXPECT_GT(p.now(), 120.0);
  EXPECT_LT(p.now(), 125.0);
}

TEST(SuturingChart, TheThreadBreakingStopsTheProcedureSafely) {
  Procedure p(2);
  p.onEntry(kAuto + "PullThread.Moving", "e_thread_broken", 0.3);
  p.run();
  EXPECT_EQ(p.leaf(), "root.SafeStop");
  const std::size_t broken = p.find("<- e_thread_broken");
  EXPECT_NE(p.find(": SutureTrajGen:askStopMove", broken), std::string::npos);
  EXPECT_NE(p.find(": emit:e_suture_safe_stop", broken), std::string::npos);
  EXPECT_EQ(p.count("> " + kAuto + "HookThread"), 0u);
}

TEST(SuturingChart, WithoutEdgesYetTheChartAsksAgainUntilThePlanComes) {
  Procedure p(1);
  p.noEdgesFirst(3);
  p.run();
  EXPECT_EQ(p.leaf(), "root.Done");
  EXPECT_EQ(p.count("> root.RetryStitchesPlan"), 3u);
  EXPECT_EQ(p.count(": Stitches:askStitch"), 3u + 2u);  // three refused, the plan, then after the stitch
}

TEST(SuturingChart, AMissedStitchIsAReaction) {
  Procedure p(1);
  p.onEntry(kAuto + "ApplyRightStitch.DisengageNeedle.Moving", "e_stitch_missed", 0.1);
  p.onEntry("root.WaitReaction", "e_recover", 1.0);
  p.run();
  EXPECT_EQ(p.leaf(), "root.Done");
  const std::size_t reaction = p.find("> root.WaitReaction");
  ASSERT_NE(reaction, std::string::npos);
  EXPECT_EQ(p.find("<- e_stitch_missed") < reaction, true);
}

TEST(SuturingChart, ToolsThatDoNotComeToRestAtTheEndAreASafeStopAfterTheRestTimeoutNamingIt) {
  Procedure p(1);
  p.neverAtRest();
  p.run();
  EXPECT_EQ(p.leaf(), "root.SafeStop");
  const std::size_t finishing = p.find("> root.Finishing");
  ASSERT_NE(finishing, std::string::npos);
  const std::size_t timeout = p.find(": emit:e_not_at_rest", finishing);
  ASSERT_NE(timeout, std::string::npos);
  EXPECT_NE(p.find(": emit:e_suture_safe_stop", timeout), std::string::npos);
  EXPECT_EQ(p.count(": emit:e_suture_task_done"), 0u);
}

}  // namespace
}  // namespace cobra::suturing
