// The two task charts (needle insertion, ultrasound positioning) loaded by cobra's rFSM loader
// and run on the statechart engine, each in its own Lua state as in two processes, coordinated
// only by the events they emit. Their peers are fakes that record the operations called and
// answer as the real components do (deployment/configuration supervisors, Frame Generator,
// planner, trajectory generator, cryoablation console); a scripted world plays the Decision
// components' events and the scenario's surgeon script plays the surgeon.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "cobra/puncturing/plan.hpp"
#include "cobra/puncturing/procedure.hpp"
#include "cobra/script/rfsm.hpp"
#include "cobra/statechart/machine.hpp"
#include "cobra/test_support/chart_fakes.hpp"

namespace cobra::puncturing {
namespace {

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/";
constexpr double kCryoCycle = 20.0;  // s from the console's e_cryo_start to its e_cryo_done (world.lua: ~19.7 s)

/// Fake peers in Lua (test_support/chart_fakes.hpp).
const std::string kFakes = test_support::fakePeersLua(
    {"NeedleFrames", "NeedlePlanner", "NeedleTrajGen", "NeedleMonitor", "NeedleTransparency", "ProbeFrames", "ProbePlanner",
     "ProbeTrajGen", "ProbeTransparency"});
using Entered = test_support::EntryLogger;

/// One chart with its own Lua state, as its own Supervisor would run it.
struct ChartRun {
  std::string name;  // "needle" or "us"
  script::LuaState lua;
  std::unique_ptr<script::RfsmChart> chart;
  std::unique_ptr<statechart::Machine> machine;
  Entered observer;
  std::vector<std::string> entries;  // every state entered, in order
  std::string deployment;            // the last deployment answered as done
  int needle = 0;                    // its Frame Generator's needle index
  int motion = 0;                    // id of the motion being executed (0: none)

  ChartRun(const std::string& chart_name, const std::string& file, const double* now) : name(chart_name) {
    lua.run(kFakes, "=fakes");
    // As the Supervisor does: the chart's folder, then cobra's charts (task_steps.lua).
    lua.run("package.path = '" + kApp + "charts/?.lua;" COBRA_CHARTS_DIR "/?.lua;' .. package.path", "=charts path");
    chart = script::RfsmChart::loadFile(lua, kApp + "charts/" + file);
    machine = std::make_unique<statechart::Machine>(chart->chart(), [now] {
      return std::chrono::nanoseconds(static_cast<long long>(*now * 1e9));
    });
    chart->bind(machine.get());
    observer.lua = &lua;
    machine->setObserver(&observer);
  }
};

/// What happens to a chart at a time: an event, tagged with the motion it answers (0: none).
struct Pending {
  double at;
  ChartRun* to;
  std::string event;
  int motion;
};

/// The procedure: two charts, their fake peers and world, the surgeon script, a clock in 10 ms ticks.
class Procedure {
 public:
  explicit Procedure(const std::string& scenario, int needles)
      : needle_("needle", "needle_insertion.lua", &now_), us_("us", "us_positioning.lua", &now_), needles_(needles) {
    script_ = parseSurgeonScript(readText(kApp + "scenarios/" + scenario + "/surgeon.txt"), scenario);
    used_.assign(script_.actions.size(), 0);
    for (const SurgeonAction& a : script_.actions) {
      if (a.trigger == SurgeonAction::Trigger::At) {
        at(a.at, &needle_, a.event);
        at(a.at, &us_, a.event);
      }
    }
  }

  /// Event `event` replaces the normal outcome the next `times` times motion `fqn` moves.
  void fault(const std::string& fqn, const std::string& event, int times = 1) { faults_[fqn] = {event, times}; }
  /// The world says `event` to chart `to` `delay` s after chart `when` enters state `state`, once.
  void onEntry(ChartRun& when, const std::string& state, ChartRun& to, const std::string& event, double delay) {
    triggers_.push_back({&when, state, &to, event, delay, false});
  }
  /// Chart `chart`'s planner refuses the whole procedure when asked to verify it.
  void refuseProcedure(ChartRun& chart) { refuse_procedure_ = &chart; }
  /// The Frame Generator's answer to awaitNavigation ("e_navigation_refused", "e_navigation_timeout").
  void navigationAnswer(std::string event) { navigation_answer_ = std::move(event); }
  /// The next `times` plans chart `chart` asks for fail.
  void failPlan(ChartRun& chart, int times = 1) {
    fail_plan_ = &chart;
    fail_plans_ = times;
  }

  /// Runs until both charts are Done or stopped safely, or `limit` s pass.
  void run(double limit = 2000.0) {
    step();
    while (now_ < limit && !(ended(needle_) && ended(us_))) {
      now_ += 0.01;
      std::stable_sort(pending_.begin(), pending_.end(), [](const Pending& a, const Pending& b) { return a.at < b.at; });
      std::vector<Pending> due;
      while (!pending_.empty() && pending_.front().at <= now_ + 1e-9) {
        due.push_back(pending_.front());
        pending_.erase(pending_.begin());
      }
      for (const Pending& p : due) {
        if (p.motion != 0 && p.motion != p.to->motion) continue;  // answers a motion that was stopped
        timeline_.push_back(p.to->name + " <- " + p.event);
        p.to->machine->raise(p.event);
      }
      step();
    }
  }

  static bool done(const ChartRun& c) { return c.machine->activeLeaf() == "root.Done"; }
  static bool stopped(const ChartRun& c) { return c.machine->activeLeaf() == "root.SafeStop"; }
  static bool ended(const ChartRun& c) { return done(c) || stopped(c); }
  double now() const { return now_; }
  ChartRun& needle() { return needle_; }
  ChartRun& us() { return us_; }
  /// "chart > state", "chart <- event", "chart: Peer:op", "chart emits e" in order of happening.
  const std::vector<std::string>& timeline() const { return timeline_; }
  std::size_t count(const std::string& line) const {
    return static_cast<std::size_t>(std::count(timeline_.begin(), timeline_.end(), line));
  }
  /// Index of the first line equal to `line` at or after `from` (npos: none).
  std::size_t find(const std::string& line, std::size_t from = 0) const {
    for (std::size_t i = from; i < timeline_.size(); ++i) {
      if (timeline_[i] == line) return i;
    }
    return std::string::npos;
  }

 private:
  struct Trigger {
    ChartRun* when;
    std::string state;
    ChartRun* to;
    std::string event;
    double delay;
    bool fired;
  };

  void at(double t, ChartRun* to, const std::string& event, int motion = 0) { pending_.push_back({t, to, event, motion}); }
  ChartRun& other(ChartRun& c) { return &c == &needle_ ? us_ : needle_; }

  void step() {
    for (bool busy = true; busy;) {
      busy = false;
      for (ChartRun* c : {&needle_, &us_}) {
        c->machine->run();
        std::istringstream lines(c->lua.evaluate("drain()"));
        for (std::string line; std::getline(lines, line);) {
          busy = true;
          if (line.starts_with("enter:")) {
            c->entries.push_back(line.substr(6));
            entered(*c, line.substr(6));
          } else {
            answer(*c, line);
          }
        }
      }
    }
  }

  void entered(ChartRun& c, const std::string& fqn) {
    timeline_.push_back(c.name + " > " + fqn);
    for (Trigger& t : triggers_) {
      if (!t.fired && t.when == &c && fqn == t.state) {
        t.fired = true;
        at(now_ + t.delay, t.to, t.event);
      }
    }
    for (std::size_t i = 0; i < script_.actions.size(); ++i) {  // the first matching line not used up fires
      const SurgeonAction& a = script_.actions[i];
      if (a.trigger != SurgeonAction::Trigger::OnState || a.chart != c.name) continue;
      if (!fqn.ends_with("." + a.state)) continue;
      if (a.times != 0 && used_[i] >= a.times) continue;
      ++used_[i];
      at(now_ + a.after, &needle_, a.event);
      at(now_ + a.after, &us_, a.event);
      break;
    }
  }

  /// The fake peers and the world answering what a chart asked for.
  void answer(ChartRun& c, const std::string& line) {
    timeline_.push_back(c.name + ": " + line);
    const std::string leaf(c.machine->activeLeaf());
    const std::string motion_fqn = leaf.substr(0, leaf.rfind('.'));
    auto reply = [&](const std::string& event, double delay = 0.02, int motion = 0) { at(now_ + delay, &c, event, motion); };
    if (line.starts_with("emit:e_deploy_")) {
      const std::string name = line.substr(14);
      reply("e_deployed_" + name);
      pending_deployment_[&c] = name;
    } else if (line.starts_with("emit:e_configure_")) {
      reply("e_configured_" + line.substr(17));
    } else if (line == "emit:e_cryo_start") {
      reply("e_cryo_done", kCryoCycle);  // the CryoConsole: a freeze, then the thaw
    } else if (line.starts_with("emit:e_us_") || line.starts_with("emit:e_needle_")) {
      at(now_ + 0.05, &other(c), line.substr(5));  // the inter-chart link
    } else if (line.ends_with("Frames:askCurrentGoal")) {
      c.deployment = pending_deployment_[&c];
      if (c.needle >= needles_) {
        reply("e_no_data");
        return;
      }
      reply("e_goal_ready");
      if (c.deployment.ends_with("_autonomous_primitives")) reply("e_path_ready", 0.03);  // desiredPoses is the path
    } else if (line.ends_with("Frames:awaitNavigation")) {
      reply(navigation_answer_);  // by default the plan and registration from the files
    } else if (line.ends_with("Planner:verifyProcedure")) {
      reply(refuse_procedure_ == &c ? "e_procedure_refused" : "e_procedure_verified", 1.0);
    } else if (line.ends_with("Planner:askPlan")) {
      if (fail_plan_ == &c && fail_plans_ > 0) {
        --fail_plans_;
        reply("e_plan_failed", 0.5);
      } else {
        reply("e_plan_done", 0.5);
        reply("e_path_ready", 0.51);
      }
    } else if (line.ends_with("TrajGen:askGenerateTraj")) {
      reply("e_trajectory_ready");
    } else if (line.ends_with("TrajGen:askStartMove")) {
      c.motion = ++motions_;
      reply("e_moving", 0.01, c.motion);
      double delay = 2.0;  // s: each Decision event half a second after the previous one
      for (const std::string& e : outcome(c, motion_fqn)) reply(e, delay += 0.5, c.motion);
    } else if (line.ends_with("TrajGen:askStopMove")) {
      if (c.motion == 0) {
        reply("e_not_moving");
      } else {
        c.motion = 0;
        reply("e_motion_stopped", 0.2);
      }
    } else if (line.ends_with("Frames:nextNeedle")) {
      reply(++c.needle >= needles_ ? "e_all_needles_done" : "e_needle_selected");
    }
  }

  /// What the world makes of a motion of state `fqn`: the Decision events that end it.
  std::vector<std::string> outcome(ChartRun& c, const std::string& fqn) {
    if (auto f = faults_.find(fqn); f != faults_.end() && f->second.second > 0) {
      --f->second.second;
      return {f->second.first};
    }
    static const std::map<std::string, std::vector<std::string>> kNormal = {
        {"root.InsertingNeedles.MoveToSkin.Descend", {"e_skin_touched"}},
        {"root.InsertingNeedles.PenetratingSkin", {"e_skin_penetrated"}},
        {"root.InsertingNeedles.MoveToTumor", {"e_target_reached", "e_motion_done"}},
        {"root.MoveToSkin.Descend", {"e_probe_contact"}},
        {"root.USPositioned.SearchingNeedle", {"e_motion_done", "e_needle_visible"}},
    };
    const auto it = kNormal.find(fqn);
    (void)c;
    return it == kNormal.end() ? std::vector<std::string>{"e_motion_done"} : it->second;
  }

  double now_ = 0.0;
  ChartRun needle_, us_;
  int needles_;
  int motions_ = 0;
  SurgeonScript script_;
  std::vector<int> used_;
  std::vector<Pending> pending_;
  std::vector<std::string> timeline_;
  std::map<std::string, std::pair<std::string, int>> faults_;
  std::vector<Trigger> triggers_;
  std::map<ChartRun*, std::string> pending_deployment_;
  ChartRun* fail_plan_ = nullptr;
  int fail_plans_ = 0;
  ChartRun* refuse_procedure_ = nullptr;
  std::string navigation_answer_ = "e_navigation_received";
};

/// The scenarios of the tests below: a scenario folder, its needle count and the faults injected.
/// Each test runs one; the coverage test runs them all (ctest runs every test in its own process).
struct Scenario {
  const char* folder;
  int needles;
  std::function<void(Procedure&)> inject = [](Procedure&) {};
};
const Scenario kNominal{"two_needles", 2};
const Scenario kForbiddenRegion{"three_needles", 3,  // its surgeon takes over at the first reaction
                                [](Procedure& p) { p.fault("root.InsertingNeedles.MoveToTumor", "e_forbidden_region"); }};
const Scenario kTrapped{"two_needles", 2, [](Procedure& p) {
                          p.fault("root.ExtractingNeedle.VerifyingNeedleTrapped", "e_needle_trapped");
                        }};
const Scenario kNeedleLost{"two_needles", 2, [](Procedure& p) {
                             p.onEntry(p.needle(), "root.InsertingNeedles.MoveToTumor.Moving", p.us(), "e_needle_lost", 0.5);
                           }};
const Scenario kPlanFailure{"two_needles", 2, [](Procedure& p) { p.failPlan(p.us()); }};
// The robot refuses a command it cannot follow continuously (e_ik_discontinuity) during the
// needle's approach: once (a reaction, then the retry succeeds), or twice in a row.
const Scenario kIkDiscontinuity{"two_needles", 2, [](Procedure& p) {
                                  p.fault("root.InsertingNeedles.MoveToSkin.Approach", "e_ik_discontinuity");
                                }};
const Scenario kIkDiscontinuityAgain{"two_needles", 2, [](Procedure& p) {
                                       p.fault("root.InsertingNeedles.MoveToSkin.Approach", "e_ik_discontinuity", 2);
                                     }};
const Scenario kPlanFailureAgain{"two_needles", 2, [](Procedure& p) { p.failPlan(p.us(), 2); }};
// No needle change pose leaves room for the probe (the planner refuses every alternative): the
// needle robot's first motion fails, and again after the reaction; the probe never moves.
const Scenario kNoRoomForProbe{"two_needles", 2, [](Procedure& p) { p.failPlan(p.needle(), 2); }};
// The whole procedure cannot be made (the planner's verifyProcedure refuses it): nothing moves.
const Scenario kRefused{"two_needles", 2, [](Procedure& p) { p.refuseProcedure(p.needle()); }};
// The needle's planner passes it, the probe's refuses it (its own seed): nothing moves either.
const Scenario kProbeRefused{"two_needles", 2, [](Procedure& p) { p.refuseProcedure(p.us()); }};
// The navigated plan refused, or not come in time (the Frame Generator's awaitNavigation): nothing moves.
const Scenario kNavigationRefused{"two_needles", 2, [](Procedure& p) { p.navigationAnswer("e_navigation_refused"); }};
const Scenario kNavigationTimeout{"two_needles", 2, [](Procedure& p) { p.navigationAnswer("e_navigation_timeout"); }};
const Scenario kThreeNeedles{"three_needles", 3};
const Scenario kMissedGoals{"three_needles", 3, [](Procedure& p) {
                              p.fault("root.InsertingNeedles.PenetratingSkin", "e_motion_done");  // no puncture
                              p.fault("root.MoveToSkin.Descend", "e_motion_done");  // no skin where it should be
                              p.onEntry(p.needle(), "root.InsertingNeedles.MoveToTumor.Moving", p.us(),
                                        "e_probe_contact_lost", 0.1);
                            }};
const Scenario kShortMotions{"two_needles", 2, [](Procedure& p) {  // its surgeon lets the system recover
                               p.fault("root.InsertingNeedles.MoveToSkin.Descend", "e_motion_done");
                               p.fault("root.InsertingNeedles.MoveToTumor", "e_motion_done");  // missed the target
                             }};

std::unique_ptr<Procedure> run(const Scenario& scenario) {
  auto p = std::make_unique<Procedure>(scenario.folder, scenario.needles);
  scenario.inject(*p);
  p->run();
  return p;
}

/// Asserts that `lines` appear in the timeline in this order.
void expectInOrder(const Procedure& p, const std::vector<std::string>& lines) {
  std::size_t at = 0;
  for (const std::string& line : lines) {
    const std::size_t found = p.find(line, at);
    if (found == std::string::npos) {
      std::string tail;
      for (std::size_t i = at; i < p.timeline().size() && i < at + 60; ++i) tail += "\n  " + p.timeline()[i];
      FAIL() << "missing, in order: " << line << "; the timeline from the last match:" << tail;
    }
    at = found + 1;
  }
}

TEST(PuncturingCharts, ANominalTwoNeedleProcedureGoesThroughThePhasesAToHOfSection49) {
  const auto run_ = run(kNominal);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle())) << p.needle().machine->activeLeaf();
  ASSERT_TRUE(Procedure::done(p.us())) << p.us().machine->activeLeaf();
  expectInOrder(p, {
      // A: both robots at their initial poses, waiting for the plan.
      "needle > root.WaitIceballConfig", "us > root.Idle",
      // The plan is loaded: the I-SUR robot first goes to a needle change pose that leaves room
      // for the probe's approach (a planned motion), then lets the probe move.
      "needle <- e_iceball_configured", "needle > root.MakeRoomForProbe.Switching", "needle: NeedlePlanner:askPlan",
      "needle: emit:e_needle_wait_us", "needle > root.WaitUSPositioning",
      // B: the UR5 moves toward the phantom, a planned free motion.
      "us <- e_needle_wait_us", "us > root.MoveToSkin.Approach.Switching", "us: ProbeFrames:askCurrentGoal",
      "us: ProbePlanner:askPlan", "us: ProbeTrajGen:askGenerateTraj", "us: ProbeTrajGen:askStartMove",
      // C: the probe touches the skin; the I-SUR robot, at the needle change pose, gets its needle.
      "us <- e_probe_contact", "us: emit:e_us_positioned", "needle <- e_us_positioned",
      "needle > root.InsertingNeedles.WaitNeedleMounted", "needle <- e_needle_mounted",
      "needle: NeedleMonitor:reset", "needle > root.InsertingNeedles.MoveToSkin.Approach.Switching",
      "needle: NeedlePlanner:askPlan",
      // D: at the phantom, the insertion starts (a motion primitive).
      "needle: emit:e_deploy_needle_autonomous_primitives", "needle > root.InsertingNeedles.MoveToSkin.Descend.Switching",
      // E: the needle touches the skin: penetration configuration.
      "needle <- e_skin_touched", "needle: emit:e_configure_needle_penetration",
      "needle > root.InsertingNeedles.PenetratingSkin.Switching",
      // F: the skin is punctured: the compliant needle insertion configuration.
      "needle <- e_skin_penetrated", "needle: emit:e_configure_needle_insertion",
      "needle > root.InsertingNeedles.MoveToTumor.Switching", "needle <- e_target_reached",
      "needle: emit:e_cryo_start", "needle > root.WaitCryoCycle", "needle <- e_cryo_done", "needle > root.ExtractingNeedle.VerifyingNeedleTrapped.Switching",
      // G: extracted, a collision-free motion to the needle change pose.
      "needle > root.ExtractingNeedle.MoveToExtractionPoint.Switching", "needle: emit:e_needle_extracted",
      "needle > root.InsertingNeedles.MoveToNeedleChange.Planning", "needle > root.InsertingNeedles.WaitNeedleRemoved",
      "needle <- e_needle_removed", "needle: NeedleFrames:nextNeedle",
      // H: the UR5 moves to the next probe pose; then the next needle goes in.
      "us <- e_needle_next", "us: ProbeFrames:nextNeedle", "us > root.MoveToSkin.Approach.Switching",
      "us <- e_probe_contact", "needle <- e_us_positioned", "needle > root.InsertingNeedles.WaitNeedleMounted",
      "needle > root.InsertingNeedles.MoveToSkin.Approach.Switching", "needle <- e_target_reached",
      "needle: emit:e_cryo_start", "needle <- e_cryo_done", "needle: emit:e_needle_extracted", "needle > root.InsertingNeedles.WaitNeedleRemoved",
      "needle <- e_all_needles_done", "needle > root.Done"});
  EXPECT_EQ(p.count("needle <- e_target_reached"), 2u);
  EXPECT_EQ(p.count("needle: emit:e_cryo_start"), 2u);  // one freeze cycle per needle
  EXPECT_EQ(p.count("needle <- e_cryo_done"), 2u);
  EXPECT_EQ(p.count("needle > root.WaitReaction"), 0u);
  EXPECT_EQ(p.count("us > root.WaitReaction"), 0u);
  EXPECT_EQ(p.count("needle <- e_needle_mounted"), 2u);
  EXPECT_EQ(p.count("needle <- e_needle_removed"), 2u);
  EXPECT_EQ(p.count("us > root.USPositioned.NeedleTracked"), 2u);
}

TEST(PuncturingCharts, AForbiddenRegionDuringMoveToTumorIsHandedToTheSurgeonWhoTakesOverThenTheInsertionResumes) {
  const auto run_ = run(kForbiddenRegion);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle())) << p.needle().machine->activeLeaf();
  expectInOrder(p, {"needle <- e_forbidden_region", "needle: NeedleTrajGen:askStopMove", "needle > root.WaitReaction",
                    "needle <- e_take_over", "needle: emit:e_deploy_needle_teleoperated",
                    "needle: emit:e_configure_needle_teleoperation", "needle > root.NeedleTeleoperation.InitHapticDevice",
                    "needle: NeedleTransparency:engage", "needle > root.NeedleTeleoperation.TeleoperationActive",
                    "needle <- e_teleop_done", "needle > root.InsertingNeedles.MoveToTumor.Switching",
                    "needle <- e_target_reached", "needle > root.WaitCryoCycle"});
  EXPECT_EQ(p.count("needle <- e_target_reached"), 3u);
}

TEST(PuncturingCharts, ANeedleTrappedByTheIceWaitsForTheThawThenIsExtracted) {
  const auto run_ = run(kTrapped);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle()));
  expectInOrder(p, {"needle <- e_cryo_done", "needle <- e_needle_trapped", "needle: NeedleTrajGen:askStopMove",
                    "needle > root.ExtractingNeedle.WaitDefreezing",
                    "needle > root.ExtractingNeedle.VerifyingNeedleTrapped.Switching",
                    "needle > root.ExtractingNeedle.MoveToExtractionPoint.Switching", "needle: emit:e_needle_extracted"});
  EXPECT_EQ(p.count("needle > root.WaitReaction"), 0u);
}

TEST(PuncturingCharts, TheUltrasoundLosingTheNeedleSearchesAgainWhileTheNeedleWaits) {
  const auto run_ = run(kNeedleLost);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle()));
  expectInOrder(p, {"us <- e_needle_lost", "us > root.USPositioned.SearchingNeedle.Switching",
                    "needle <- e_us_needle_lost", "needle: NeedleTrajGen:askStopMove",
                    "needle > root.InsertingNeedles.MoveToTumor.Paused", "us <- e_needle_visible",
                    "us > root.USPositioned.NeedleTracked", "needle <- e_us_needle_tracked",
                    "needle > root.InsertingNeedles.MoveToTumor.Switching", "needle <- e_target_reached"});
  EXPECT_EQ(p.count("needle <- e_target_reached"), 2u);  // the stopped motion's outcome never arrived
}

TEST(PuncturingCharts, APlannerFailureIsAReactionTheSurgeonRecoversFrom) {
  const auto run_ = run(kPlanFailure);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.us()));
  expectInOrder(p, {"us: ProbePlanner:askPlan", "us <- e_plan_failed", "us > root.WaitReaction", "us <- e_recover",
                    "us > root.MoveToSkin.Approach.Switching", "us: ProbePlanner:askPlan", "us <- e_probe_contact"});
}

TEST(PuncturingCharts, AnIkDiscontinuityDuringAMotionStopsItAndIsAReactionThenTheRetrySucceeds) {
  const auto run_ = run(kIkDiscontinuity);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle())) << p.needle().machine->activeLeaf();
  ASSERT_TRUE(Procedure::done(p.us())) << p.us().machine->activeLeaf();
  // (A state's entry actions come before the line that says it was entered.)
  expectInOrder(p, {"needle > root.InsertingNeedles.MoveToSkin.Approach.Moving", "needle <- e_ik_discontinuity",
                    "needle: NeedleTrajGen:askStopMove", "needle: emit:e_needle_reaction_needed",
                    "needle > root.WaitReaction", "needle <- e_recover",
                    "needle > root.InsertingNeedles.MoveToSkin.Approach.Switching", "needle: NeedlePlanner:askPlan",
                    "needle > root.InsertingNeedles.MoveToSkin.Descend.Switching", "needle <- e_target_reached"});
  EXPECT_EQ(p.count("needle > root.SafeStop"), 0u);
  EXPECT_EQ(p.count("needle <- e_target_reached"), 2u);
}

TEST(PuncturingCharts, TheSameIkDiscontinuityAgainOnTheRetryEndsBothChartsInTheirSafeStop) {
  const auto run_ = run(kIkDiscontinuityAgain);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::stopped(p.needle())) << p.needle().machine->activeLeaf();
  ASSERT_TRUE(Procedure::stopped(p.us())) << p.us().machine->activeLeaf();
  expectInOrder(p, {"needle <- e_ik_discontinuity", "needle > root.WaitReaction", "needle <- e_recover",
                    "needle > root.InsertingNeedles.MoveToSkin.Approach.Switching", "needle <- e_ik_discontinuity",
                    "needle: NeedleTrajGen:askStopMove", "needle: emit:e_needle_safe_stop", "needle > root.SafeStop",
                    "us <- e_needle_safe_stop", "us: ProbeTrajGen:askStopMove", "us: emit:e_us_safe_stop",
                    "us > root.SafeStop"});
  EXPECT_EQ(p.count("needle > root.WaitReaction"), 1u);  // one reaction, not a loop of retries
  EXPECT_EQ(p.count("needle <- e_target_reached"), 0u);
  EXPECT_LT(p.now(), 100.0) << "s: it ended, it did not run to the limit";
}

TEST(PuncturingCharts, APlannerFailingTwiceForTheSameGoalEndsInTheSafeStop) {
  const auto run_ = run(kPlanFailureAgain);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::stopped(p.us())) << p.us().machine->activeLeaf();
  ASSERT_TRUE(Procedure::stopped(p.needle())) << p.needle().machine->activeLeaf();
  expectInOrder(p, {"us: ProbePlanner:askPlan", "us <- e_plan_failed", "us > root.WaitReaction", "us <- e_recover",
                    "us > root.MoveToSkin.Approach.Switching", "us: ProbePlanner:askPlan", "us <- e_plan_failed",
                    "us: emit:e_us_safe_stop", "us > root.SafeStop", "needle <- e_us_safe_stop",
                    "needle: emit:e_needle_safe_stop", "needle > root.SafeStop"});
  EXPECT_EQ(p.count("us > root.WaitReaction"), 1u);
}

TEST(PuncturingCharts, NoRoomForTheProbeEndsInTheSafeStopBeforeTheProbeMoves) {
  const auto run_ = run(kNoRoomForProbe);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::stopped(p.needle())) << p.needle().machine->activeLeaf();
  ASSERT_TRUE(Procedure::stopped(p.us())) << p.us().machine->activeLeaf();
  expectInOrder(p, {"needle > root.MakeRoomForProbe.Switching", "needle: NeedlePlanner:askPlan",
                    "needle <- e_plan_failed", "needle > root.WaitReaction", "needle <- e_recover",
                    "needle > root.MakeRoomForProbe.Switching", "needle: NeedlePlanner:askPlan",
                    "needle <- e_plan_failed", "needle > root.SafeStop", "us <- e_needle_safe_stop",
                    "us > root.SafeStop"});
  EXPECT_EQ(p.count("us: ProbePlanner:askPlan"), 0u);  // the probe waited for room and never moved
  EXPECT_EQ(p.count("needle: emit:e_needle_wait_us"), 0u);
}

TEST(PuncturingCharts, MissedGoalsContactLossAndTakeOverOfTheProbe) {
  const auto run_ = run(kMissedGoals);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle())) << p.needle().machine->activeLeaf();
  expectInOrder(p, {"us > root.MoveToSkin.Descend.Arrived", "us: emit:e_us_goal_missed", "us > root.WaitReaction",
                    "us <- e_take_over", "us > root.USTeleoperation", "us <- e_teleop_done",
                    "us > root.MoveToSkin.Descend.Switching", "us <- e_probe_contact_lost", "us > root.WaitReaction",
                    "us <- e_recover", "us > root.USPositioned.NeedleTracked"});
  expectInOrder(p, {"needle > root.InsertingNeedles.PenetratingSkin.Arrived", "needle > root.WaitReaction",
                    "needle <- e_take_over", "needle > root.NeedleTeleoperation", "needle <- e_teleop_done",
                    "needle > root.InsertingNeedles.PenetratingSkin.Switching", "needle <- e_skin_penetrated"});
}

TEST(PuncturingCharts, ANeedleMotionThatEndsShortOfItsEventIsAReactionAndIsRetried) {
  const auto run_ = run(kShortMotions);
  Procedure& p = *run_;
  ASSERT_TRUE(Procedure::done(p.needle())) << p.needle().machine->activeLeaf();
  expectInOrder(p, {"needle > root.InsertingNeedles.MoveToSkin.Descend.Arrived", "needle: emit:e_needle_goal_missed",
                    "needle > root.WaitReaction", "needle <- e_recover",
                    "needle > root.InsertingNeedles.MoveToSkin.Descend.Switching", "needle <- e_skin_touched",
                    "needle > root.InsertingNeedles.MoveToTumor.Arrived", "needle > root.WaitReaction",
                    "needle <- e_recover", "needle > root.InsertingNeedles.MoveToTumor.Switching",
                    "needle <- e_target_reached"});
}

/// Both charts in their safe stops without having asked for a plan or a motion.
void expectNothingPlannedOrMoved(Procedure& p) {
  EXPECT_TRUE(Procedure::stopped(p.needle())) << p.needle().machine->activeLeaf();
  EXPECT_TRUE(Procedure::stopped(p.us())) << p.us().machine->activeLeaf();
  for (const char* request : {"needle: NeedlePlanner:askPlan", "us: ProbePlanner:askPlan",
                              "needle: NeedleTrajGen:askStartMove", "us: ProbeTrajGen:askStartMove"})
    EXPECT_EQ(p.count(request), 0u) << request;
}

TEST(PuncturingCharts, ARefusedProcedureStopsBeforeAnyMotion) {
  const auto run_ = run(kRefused);
  Procedure& p = *run_;
  // (A state's entry actions come before the line saying it was entered.)
  expectInOrder(p, {"needle <- e_iceball_configured", "needle: NeedleFrames:awaitNavigation",
                    "needle > root.WaitNavigation", "needle <- e_navigation_received",
                    "needle: NeedlePlanner:verifyProcedure",
                    "needle > root.VerifyingProcedure", "needle <- e_procedure_refused",
                    "needle: emit:e_needle_procedure_refused", "needle > root.Refused", "needle > root.SafeStop",
                    "us <- e_needle_safe_stop", "us > root.SafeStop"});
  expectNothingPlannedOrMoved(p);
}

TEST(PuncturingCharts, AProcedureOnlyTheProbesPlannerRefusesStopsBeforeAnyMotion) {
  const auto run_ = run(kProbeRefused);
  Procedure& p = *run_;
  // The probe's planner walks it only once the needle's passed it, and the needle robot waits
  // for that verdict before its first motion.
  expectInOrder(p, {"needle: NeedlePlanner:verifyProcedure", "needle <- e_procedure_verified",
                    "needle: emit:e_needle_procedure_verified", "needle > root.WaitProbeVerdict",
                    "us <- e_needle_procedure_verified", "us: ProbePlanner:verifyProcedure",
                    "us <- e_procedure_refused", "us: emit:e_us_procedure_refused", "us > root.Refused",
                    "us > root.SafeStop", "needle <- e_us_safe_stop", "needle > root.SafeStop"});
  EXPECT_EQ(p.count("us: ProbePlanner:verifyProcedure"), 1u);
  expectNothingPlannedOrMoved(p);
}

TEST(PuncturingCharts, TheNeedleRobotMovesOnlyOnceBothPlannersPassedTheProcedure) {
  const auto run_ = run(kNominal);
  Procedure& p = *run_;
  expectInOrder(p, {"needle <- e_procedure_verified", "us: ProbePlanner:verifyProcedure", "us <- e_procedure_verified",
                    "us: emit:e_us_procedure_verified", "needle <- e_us_procedure_verified",
                    "needle > root.MakeRoomForProbe.Switching"});
}

TEST(PuncturingCharts, ANavigatedPlanRefusedOrNotComeStopsBeforeTheVerificationAndAnyMotion) {
  for (const Scenario* scenario : {&kNavigationRefused, &kNavigationTimeout}) {
    const auto run_ = run(*scenario);
    Procedure& p = *run_;
    ASSERT_TRUE(Procedure::stopped(p.needle())) << p.needle().machine->activeLeaf();
    ASSERT_TRUE(Procedure::stopped(p.us())) << p.us().machine->activeLeaf();
    const std::string answer = scenario == &kNavigationRefused ? "e_navigation_refused" : "e_navigation_timeout";
    expectInOrder(p, {"needle <- e_iceball_configured", "needle: NeedleFrames:awaitNavigation",
                      "needle > root.WaitNavigation", "needle <- " + answer, "needle > root.Refused",
                      "needle > root.SafeStop", "us <- e_needle_safe_stop", "us > root.SafeStop"});
    for (const char* request : {"needle: NeedlePlanner:verifyProcedure", "needle: NeedlePlanner:askPlan",
                                "us: ProbePlanner:askPlan", "needle: NeedleTrajGen:askStartMove",
                                "us: ProbeTrajGen:askStartMove"})
      EXPECT_EQ(p.count(request), 0u) << answer << ": " << request;
  }
}

/// Each chart's motion states in the order it ran them, with the needle it was at: what
/// procedureSteps declares for the verification walk.
std::map<std::size_t, std::vector<std::string>> motionsRun(const Procedure& p) {
  std::map<std::size_t, std::vector<std::string>> motions;
  std::map<std::string, std::size_t> needle{{"needle", 0}, {"us", 0}};
  const std::string asking = ".AskingGoal", planning = ".Planning";
  for (const std::string& line : p.timeline()) {
    std::string chart = line.substr(0, line.find(' '));  // "needle > STATE", "needle: REQUEST"
    if (chart.ends_with(':')) chart.pop_back();
    const std::size_t arm = chart == "needle" ? 0 : 1;
    if (line.ends_with("Frames:nextNeedle")) ++needle[chart];
    const std::size_t enter = line.find(" > ");
    if (enter == std::string::npos) continue;
    const std::string state = line.substr(enter + 3);
    if (state.ends_with(asking)) {
      motions[arm].push_back(state.substr(0, state.size() - asking.size()) + " primitive needle " +
                             std::to_string(needle[chart]));
    } else if (state.ends_with(planning) && !motions[arm].empty()) {
      std::string& last = motions[arm].back();
      last.replace(last.find(" primitive "), 11, " planned ");
    }
  }
  return motions;
}

TEST(PuncturingCharts, TheChartsRunTheMotionStatesTheVerificationWalks) {
  for (const Scenario* scenario : {&kNominal, &kThreeNeedles}) {
    const auto p = run(*scenario);
    ASSERT_TRUE(Procedure::done(p->needle()) && Procedure::done(p->us())) << scenario->folder;
    std::map<std::size_t, std::vector<std::string>> declared;
    for (const task::ProcedureStep& step : procedureSteps(static_cast<std::size_t>(scenario->needles)))
      declared[step.arm].push_back(step.state + (step.planned ? " planned" : " primitive") + " needle " +
                                   std::to_string(step.item));
    EXPECT_EQ(motionsRun(*p), declared) << scenario->folder;
  }
}

TEST(PuncturingCharts, EveryStateOfBothChartsIsEnteredAcrossTheScenariosOfTheTests) {
  std::map<std::string, std::set<std::string>> entered;
  for (const Scenario* scenario : {&kNominal, &kForbiddenRegion, &kTrapped, &kNeedleLost, &kPlanFailure, &kMissedGoals,
                                   &kShortMotions, &kIkDiscontinuity, &kIkDiscontinuityAgain, &kPlanFailureAgain,
                                   &kNoRoomForProbe, &kRefused, &kProbeRefused, &kNavigationRefused}) {
    const auto p = run(*scenario);
    for (ChartRun* c : {&p->needle(), &p->us()}) entered[c->name].insert(c->entries.begin(), c->entries.end());
  }
  const auto covered = [&]() -> std::map<std::string, std::set<std::string>>& { return entered; };
  for (const auto& [name, file] : {std::pair{"needle", "needle_insertion.lua"}, std::pair{"us", "us_positioning.lua"}}) {
    script::LuaState lua;
    lua.run(kFakes, "=fakes");
    // As the Supervisor does: the chart's folder, then cobra's charts (task_steps.lua).
    lua.run("package.path = '" + kApp + "charts/?.lua;" COBRA_CHARTS_DIR "/?.lua;' .. package.path", "=charts path");
    const auto chart = script::RfsmChart::loadFile(lua, kApp + "charts/" + file);
    std::vector<std::string> missing;
    for (const auto& node : chart->chart().nodes()) {
      if (node.kind != statechart::NodeKind::State || node.fqn == "root") continue;
      if (!covered()[name].count(node.fqn)) missing.push_back(node.fqn);
    }
    std::string list;
    for (const auto& m : missing) list += " " + m;
    EXPECT_TRUE(missing.empty()) << name << " states never entered:" << list;
  }
  // The states the thesis names (§4.4.1, §4.4.2) are all there.
  for (const char* state : {"WaitIceballConfig", "WaitUSPositioning", "InsertingNeedles", "MoveToNeedleChange",
                            "WaitNeedleMounted", "MoveToSkin", "PenetratingSkin", "MoveToTumor", "WaitNeedleRemoved",
                            "WaitCryoCycle", "WaitReaction", "NeedleTeleoperation", "ExtractingNeedle",
                            "VerifyingNeedleTrapped", "WaitDefreezing", "MoveToExtractionPoint"}) {
    EXPECT_TRUE(std::any_of(covered()["needle"].begin(), covered()["needle"].end(),
                            [&](const std::string& fqn) { return pathContains(fqn, state); })) << state;
  }
  for (const char* state : {"MoveToSkin", "WaitNeedleSkinReached", "USPositioned", "SearchingNeedle", "NeedleTracked",
                            "WaitReaction", "USTeleoperation"}) {
    EXPECT_TRUE(std::any_of(covered()["us"].begin(), covered()["us"].end(),
                            [&](const std::string& fqn) { return pathContains(fqn, state); })) << state;
  }
}

}  // namespace
}  // namespace cobra::puncturing
