// The puncturing task end to end in simulation through the runner's API (cobra/run/runner.hpp,
// what `cobra run apps/puncturing` does): puncturing.lua — the simulated world, both robots'
// controllers with their three supervisors, three deployments and three configurations each —
// run on the lockstep clock with the scripted surgeon, nominal and with the faults files of
// test/faults/. Each test is one procedure (about 100 s simulated). Every scenario's nominal run
// also meets the procedure acceptance's fidelity (procedure_expectations.hpp).

#include "cobra/run/runner.hpp"

#include <gtest/gtest.h>

#include "procedure_expectations.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using namespace testing;

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// "fault FILE:LINE" of test/faults/`file`: the log's line when that fault was played.
std::string fault(const std::string& file, int line) { return "fault " + (kFaults / file).string() + ":" + std::to_string(line); }

/// The two-needle procedure with the faults file `faults` of test/faults/.
RunOptions withFaults(const std::string& faults) {
  RunOptions o = options("two_needles");
  o.faults_file = kFaults / faults;
  return o;
}

TEST(PuncturingProcedure, TheNominalTwoNeedleProcedureCompletesThroughThePhasesAToH) {
  RunOptions o = options("two_needles");
  o.report_folder =  // per process: other checkouts may run the same test at the same time
      std::filesystem::temp_directory_path() / ("cobra_puncturing_nominal_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  // The run folder: the event log, the recorded signals and the HTML report with its summary.
  EXPECT_EQ(r.report, o.report_folder / "report.html");
  const std::string events = readFile(o.report_folder / "events.csv");
  EXPECT_EQ(events.rfind("time [s],source,event,state\n", 0), 0u);
  EXPECT_CONTAINS(events, ",NeedleMonitor,e_target_reached");
  const std::string signals = readFile(o.report_folder / "signals.csv");
  EXPECT_EQ(signals.rfind("time [s],ISUR.measCartPose.x [m],ISUR.measCartPose.y [m],ISUR.measCartPose.z [m]", 0), 0u);
  EXPECT_GT(std::count(signals.begin(), signals.end(), '\n'), 10000);  // every 10 ms for > 100 s
  const std::string html = readFile(r.report);
  EXPECT_CONTAINS(html, "2 of 2");
  EXPECT_CONTAINS(html, "signals.csv");
  EXPECT_CONTAINS(html, "Needle-tip force against depth");
  EXPECT_CONTAINS(html, "Tool tracking error, I-SUR needle");
  EXPECT_CONTAINS(html, "Tool tracking error, UR5 probe");
  EXPECT_CONTAINS(html, "error [deg]");
  EXPECT_CONTAINS(html, "clearance threshold");
  EXPECT_CONTAINS(html, "allowed contact 'needle in tissue', smallest distance (0: touching or inside)");
  EXPECT_CONTAINS(html, "allowed contact 'probe on skin', smallest distance");
  EXPECT_CONTAINS(html, "worst tracking, I-SUR needle (while the needle deployment is needle_autonomous_planning or "
                        "needle_autonomous_primitives)");
  EXPECT_CONTAINS(html, "worst clearance (threshold 5.00 mm, allowed contacts apart)");
  EXPECT_CONTAINS(html, "Energy tanks of the variable admittances");
  EXPECT_CONTAINS(signals, ",tracking.I-SUR needle.mm [mm],tracking.I-SUR needle.deg [deg],tracking.UR5 probe.mm [mm],"
                           "tracking.UR5 probe.deg [deg],");
  EXPECT_CONTAINS(signals, ",contact.probe on skin [m],contact.needle in tissue [m],clearance [m],clearance.threshold [m],"
                           "clearance.macro/micro [m],clearance.macro/ur5 [m],clearance.micro/ur5 [m],"
                           "clearance.micro/environment [m],clearance.ur5/environment [m]\n");
  // The clearance per pair of groups (the planner's pairDistances): each above the threshold.
  ASSERT_EQ(r.clearance.pairs.size(), 5u);
  EXPECT_EQ(r.clearance.pairs[2].name, "micro/ur5");
  for (const ClearanceFigures::Pair& pair : r.clearance.pairs) EXPECT_GT(pair.worst, r.clearance.threshold) << pair.name;
  EXPECT_CONTAINS(html, "Clearance per pair of groups (NeedlePlanner.pairDistances)");
  EXPECT_CONTAINS(html, "clearance of the pair micro/ur5 (its smallest)");
  // One configuration row per scope in the timeline, no row mixing both robots' configurations.
  EXPECT_CONTAINS(html, ">needle configuration</text>");
  EXPECT_CONTAINS(html, ">probe configuration</text>");
  EXPECT_EQ(html.find(">configuration</text>"), std::string::npos);
  // The nominal procedure's own events (the needle pulled out of the image, the probe leaving the
  // skin for the next needle) are expected task events, not faults.
  EXPECT_EQ(r.value("faults detected").text, "0");
  EXPECT_EQ(r.value("expected task events").text, "e_needle_lost x2, e_probe_contact_lost x1");
  expectInOrder(r, {
      // A: both robots at their initial poses; the surgeon configures the iceballs. The I-SUR
      // robot's initial pose is the first needle change pose, which leaves room for the probe.
      "needle > root.WaitIceballConfig", "us > root.Idle", "Surgeon: e_iceball_configured",
      "needle > root.MakeRoomForProbe", "NeedlePlanner: e_plan_done", "needle > root.WaitUSPositioning",
      // B: the UR5 plans a collision-free path to the first probe pose and descends to contact.
      "us > root.MoveToSkin.Approach", "ProbePlanner: e_plan_done", "us > root.MoveToSkin.Descend",
      "probe deployment > probe_autonomous_primitives", "USMonitor: e_probe_contact", "us > root.WaitNeedleSkinReached",
      // C: the I-SUR robot waits at the needle change pose; the surgeon mounts the needle.
      "needle > root.InsertingNeedles.WaitNeedleMounted", "Surgeon: e_needle_mounted",
      // D: a planned motion above the entry point, then a motion primitive to the skin.
      "needle > root.InsertingNeedles.MoveToSkin.Approach", "NeedlePlanner: e_plan_done",
      "needle > root.InsertingNeedles.MoveToSkin.Descend", "needle deployment > needle_autonomous_primitives",
      // E: the skin touched: the penetration configuration; the probe searches the needle.
      "NeedleMonitor: e_skin_touched", "needle > root.InsertingNeedles.PenetratingSkin",
      "us > root.USPositioned.SearchingNeedle", "NeedleConfSup: e_configured_needle_penetration",
      // F: the skin punctured: the insertion configuration to the tumour, guided by the image.
      "NeedleMonitor: e_skin_penetrated", "needle > root.InsertingNeedles.MoveToTumor",
      "NeedleConfSup: e_configured_needle_insertion", "us > root.USPositioned.NeedleTracked",
      "NeedleMonitor: e_target_reached", "needle > root.WaitCryoCycle", "Cryo: e_cryo_done",
      // G: the needle is free of ice and comes out; a planned motion to the needle change pose.
      "needle > root.ExtractingNeedle.VerifyingNeedleTrapped", "needle > root.ExtractingNeedle.MoveToExtractionPoint",
      "needle > root.InsertingNeedles.MoveToNeedleChange", "needle deployment > needle_autonomous_planning",
      "needle > root.InsertingNeedles.WaitNeedleRemoved", "Surgeon: e_needle_removed",
      // H: the probe moves to the second needle's pose; the second needle goes in the same way.
      "needle > root.WaitUSPositioning", "us > root.MoveToSkin.Approach", "USMonitor: e_probe_contact",
      "needle > root.InsertingNeedles.WaitNeedleMounted", "Surgeon: e_needle_mounted", "NeedleMonitor: e_skin_touched",
      "NeedleMonitor: e_target_reached", "Cryo: e_cryo_done", "needle > root.InsertingNeedles.WaitNeedleRemoved",
      "needle > root.Done", "us > root.Done"});
  EXPECT_EQ(count(r, "needle > root.WaitReaction"), 0u);
  EXPECT_EQ(count(r, "us > root.WaitReaction"), 0u);
  EXPECT_EQ(count(r, "NeedleMonitor: e_target_reached"), 2u);
  expectNoCommandJump(r);
  expectFaithful(r);
}

// The second scenario: three needles, a larger tumour off the midline, the abdomen turned 0.3 rad.
TEST(PuncturingProcedure, TheThreeNeedleScenarioCompletesWithEveryNeedlePlaced) {
  const RunResult r = runApp(options("three_needles"));
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 3);
  EXPECT_EQ(count(r, "NeedleMonitor: e_target_reached"), 3u);
  EXPECT_EQ(count(r, "needle > root.WaitReaction"), 0u);
  EXPECT_EQ(count(r, "us > root.WaitReaction"), 0u);
  expectInOrder(r, {"needle > root.WaitCryoCycle", "needle > root.InsertingNeedles.WaitNeedleRemoved",
                    "needle > root.WaitCryoCycle", "needle > root.InsertingNeedles.WaitNeedleRemoved",
                    "needle > root.WaitCryoCycle", "needle > root.Done", "us > root.Done"});
  expectNoCommandJump(r);
  expectFaithful(r);
}

// The needle vertical: the I-SUR's yaw-pitch-roll wrist at its singular pose. The
// scenario comes with the joint-aware planning; until it is there this test says so and skips.
TEST(PuncturingProcedure, TheVerticalNeedleScenarioCompletesFaithfully) {
  const std::filesystem::path scenario = kApp / "scenarios" / "vertical_needle";
  if (!std::filesystem::exists(scenario / "cryo_plan.txt")) GTEST_SKIP() << scenario << " does not exist yet";
  const RunResult r = runApp(options(scenario));
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, plannedNeedles(scenario));
  EXPECT_EQ(count(r, "needle > root.WaitReaction"), 0u);
  EXPECT_EQ(count(r, "us > root.WaitReaction"), 0u);
  expectFaithful(r);
}

TEST(PuncturingProcedure, AForbiddenRegionIsTakenOverInTeleoperationWithoutACommandJumpThenTheInsertionResumes) {
  // The monitor's margin grows to 10 cm in MoveToTumor (the tip "near" the rib), and is back to
  // 1 mm once the surgeon has the needle; the surgeon's first reaction is a take-over.
  RunOptions o = withFaults("forbidden_region.lua");
  o.before_lua = "surgeon_file = [[" + (kFaults / "take_over_surgeon.txt").string() + "]]";
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  expectInOrder(r, {"NeedleMonitor: e_skin_penetrated", "needle > root.InsertingNeedles.MoveToTumor",
                    fault("forbidden_region.lua", 6), "NeedleMonitor: e_forbidden_region", "needle > root.WaitReaction", "Surgeon: e_take_over",
                    "needle > root.NeedleTeleoperation.InitHapticDevice", "needle deployment > needle_teleoperated",
                    "needle > root.NeedleTeleoperation.TeleoperationActive",
                    fault("forbidden_region.lua", 8), "Surgeon: e_teleop_done", "needle > root.InsertingNeedles.MoveToTumor",
                    "needle deployment > needle_autonomous_primitives", "NeedleMonitor: e_target_reached",
                    "needle > root.WaitCryoCycle"});
  // Autonomous -> teleoperated -> autonomous with the needle in tissue: the commanded pose (the
  // admittance's output) never jumps between two 1 ms steps.
  expectNoCommandJump(r);
}

TEST(PuncturingProcedure, ANeedleTrappedByTheIceWaitsForTheThawThenIsExtracted) {
  // The console reports the thaw while the iceball still holds the needle.
  const RunResult r = runApp(withFaults("needle_trapped.lua"));
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  expectInOrder(r, {fault("needle_trapped.lua", 4), "Cryo: e_cryo_done",
                    "needle > root.ExtractingNeedle.VerifyingNeedleTrapped",
                    "NeedleMonitor: e_needle_trapped", "needle > root.ExtractingNeedle.WaitDefreezing",
                    "NeedleMonitor: e_needle_free", "needle > root.ExtractingNeedle.VerifyingNeedleTrapped",
                    "needle > root.ExtractingNeedle.MoveToExtractionPoint",
                    "needle > root.InsertingNeedles.MoveToNeedleChange"});
  EXPECT_GE(count(r, "needle > root.ExtractingNeedle.WaitDefreezing"), 2u);  // both needles
  EXPECT_EQ(count(r, "needle > root.WaitReaction"), 0u);
}

TEST(PuncturingProcedure, TheUltrasoundLosingTheNeedlePausesTheInsertionUntilItIsTrackedAgain) {
  // The image processing loses the needle 0.3 s after the probe tracks it, and sees it again 1 s
  // after the insertion paused.
  const RunResult r = runApp(withFaults("needle_lost.lua"));
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  // Lost mid-insertion, it is a fault; as each needle is pulled out, an expected task event.
  EXPECT_EQ(r.value("faults detected").text, "1");
  EXPECT_EQ(r.value("expected task events").text, "e_needle_lost x2, e_probe_contact_lost x1");
  expectInOrder(r, {"needle > root.InsertingNeedles.MoveToTumor", fault("needle_lost.lua", 5),
                    fault("needle_lost.lua", 7), "USMonitor: e_needle_lost", "us > root.USPositioned.SearchingNeedle",
                    fault("needle_lost.lua", 9), fault("needle_lost.lua", 11), "USMonitor: e_needle_visible",
                    "us > root.USPositioned.NeedleTracked", "NeedleMonitor: e_target_reached",
                    "needle > root.WaitCryoCycle"});
}

TEST(PuncturingProcedure, APlannerFailureIsAReactionAndTheRetryAfterRecoverySucceeds) {
  // 0.5 m of required clearance from the needle robot's first motion (MakeRoomForProbe) on: every
  // state is "too close"; restored in WaitReaction.
  const RunResult r = runApp(withFaults("planner_fails_once.lua"));
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  expectInOrder(r, {"needle > root.MakeRoomForProbe", fault("planner_fails_once.lua", 5),
                    "NeedlePlanner: e_plan_failed", "needle > root.WaitReaction", fault("planner_fails_once.lua", 10),
                    "Surgeon: e_recover", "needle > root.MakeRoomForProbe", "NeedlePlanner: e_plan_done",
                    "needle > root.WaitUSPositioning", "us > root.MoveToSkin.Approach"});
  EXPECT_EQ(count(r, "NeedlePlanner: e_plan_failed"), 1u);
}

// No goal alternative the planner can take (every state "too close" from the needle robot's first
// motion on: none of the needle change poses of MakeRoomForProbe leaves room): the
// reaction's retry fails the same way, so both charts end in their safe stop, at once, saying why.
TEST(PuncturingProcedure, APlannerFailingAgainOnTheRetryEndsTheProcedureInTheSafeStopWithTheReason) {
  const RunResult r = runApp(withFaults("planner_fails_again.lua"));
  EXPECT_FALSE(r.completed());
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << "ended at " << r.duration << " s: " << r.reason;
  EXPECT_LT(r.duration, 60.0) << "s: the run ends at the safe stop, not at the time limit";
  expectInOrder(r, {"needle > root.MakeRoomForProbe", fault("planner_fails_again.lua", 4),
                    "NeedlePlanner: e_plan_failed", "needle > root.WaitReaction", "Surgeon: e_recover",
                    "needle > root.MakeRoomForProbe", "NeedlePlanner: e_plan_failed",
                    "needle > root.SafeStop", "us > root.SafeStop"});
  EXPECT_EQ(count(r, fault("planner_fails_again.lua", 4)), 1u);
  EXPECT_EQ(count(r, "needle safe stop"), 1u);
  EXPECT_EQ(count(r, "NeedlePlanner: e_plan_failed"), 2u);
  EXPECT_CONTAINS(r.reason, "needle chart stopped safely in root.MakeRoomForProbe: "
                            "NeedlePlanner: e_plan_failed at");
  EXPECT_CONTAINS(r.reason, "the same failure again after the reaction to the first, no answer in time (charts/waits.lua), "
                            "or the procedure refused before any motion (VerifyingProcedure); "
                            "NeedlePlanner.lastPlanResult(): ");
  // Each needle change pose is named with why it cannot be taken.
  EXPECT_CONTAINS(r.reason, "none of the 3 goal alternatives can be taken from first (");
  EXPECT_CONTAINS(r.reason, ": goal 1 of 3 first (-0.0500, 0.0500, 0.2600 m;");
  EXPECT_CONTAINS(r.reason, "; goal 3 of 3 first (-0.0900, 0.0700, 0.2300 m;");
  EXPECT_CONTAINS(r.reason, "too close");
  // Stopped before anything moved: the probe waited for room and was never planned for.
  EXPECT_EQ(count(r, "us > root.MoveToSkin.Approach"), 0u);
  expectTracked(r);
  expectClear(r);
}

// The planner fails from the first motion on and the surgeon never reacts: the needle chart waits
// in WaitReaction for charts/waits.lua's surgeon timeout (120 s), then stops safely naming it, and
// the probe's chart stops with it.
TEST(PuncturingProcedure, ASurgeonWhoNeverReactsEndsTheProcedureInTheSafeStopNamingTheTimeout) {
  RunOptions o = withFaults("planner_fails_again.lua");
  o.before_lua = "surgeon_file = [[" + (kFaults / "silent_surgeon.txt").string() + "]]";
  const RunResult r = runApp(o);
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << "ended at " << r.duration << " s: " << r.reason;
  expectInOrder(r, {"NeedlePlanner: e_plan_failed", "needle > root.WaitReaction", "NeedleTaskSup: e_reaction_timeout",
                    "needle > root.SafeStop", "us > root.SafeStop"});
  EXPECT_CONTAINS(r.reason, "needle chart stopped safely in root.WaitReaction: NeedleTaskSup: e_reaction_timeout at");
  EXPECT_EQ(count(r, "Surgeon: e_recover"), 0u);
}

// The needle's task chart wrapped so that the entry of MakeRoomForProbe.Moving (the first motion)
// starts the motion, then calls a function that does not exist: loaded as `cobra run` loads it,
// on the lockstep clock. NeedleTaskSup goes to Exception naming the wrapper's line; its chart's
// exceptionHook stops the needle and tells the probe's chart, which stops safely too.
TEST(PuncturingProcedure, ALuaErrorInTheNeedleChartStopsTheNeedleAndTheProbesChartFollows) {
  using namespace std::chrono_literals;
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.runFile((kApp / "puncturing.lua").string());
  const std::string charts = (kApp / "charts").string();
  const std::string wrapper = ::cobra::test_support::scratchPath("needle_insertion_broken.lua").string();
  std::ofstream(wrapper) << "package.path = '" << charts << "/?.lua;' .. package.path\n"
                         << "local chart = dofile('" << charts << "/needle_insertion.lua')\n"
                         << "local moving = chart.MakeRoomForProbe.Moving\n"
                         << "local start = moving.entry\n"
                         << "moving.entry = function(...) start(...) stopp() end\n"
                         << "return chart\n";
  deployer.run("stopComponents({'NeedleTaskSup'}) cleanupComponents({'NeedleTaskSup'}) NeedleTaskSup.fsm_path = [[" +
                   wrapper + "]] configureComponents({'NeedleTaskSup'}) startComponents({'NeedleTaskSup'})",
               "=wrap the chart");
  const core::ComponentRegistry& refs = configurator.getReferences();
  core::Component& needle = refs.get("NeedleTaskSup");
  core::InputPort<KDL::Frame> measured{"measured", "", "m"};
  core::connectPorts(refs.get("ISUR").port("measCartPose"), measured);
  core::InputPort<core::TaskState> probe_state{"probe_state", "", ""};
  core::connectPorts(refs.get("ProbeTaskSup").port("taskState"), probe_state);
  double t = 0.0;
  for (; t < 60.0 && needle.state() == core::State::Running; t += 0.01) configurator.clock().advance(10ms);
  ASSERT_EQ(needle.state(), core::State::Exception) << "at " << t << " s";
  EXPECT_EQ(needle.lastError(), "component 'NeedleTaskSup': updateHook threw: entry of root.MakeRoomForProbe.Moving "
                                "failed: " + wrapper + ":5: attempt to call a nil value (global 'stopp')");
  configurator.clock().advance(600ms);  // past the trajectory generator's stop motion
  core::TaskState probe;
  ASSERT_EQ(probe_state.read(probe), core::FlowStatus::NewData);
  EXPECT_EQ(probe.path.str(), "root.SafeStop");
  KDL::Frame then, later;
  ASSERT_NE(measured.read(then), core::FlowStatus::NoData);
  configurator.clock().advance(2s);
  ASSERT_NE(measured.read(later), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(then, later, 1e-6)) << "moved by " << (later.p - then.p).Norm() << " m";
}

// The I-SUR refuses a command mid-motion (slowed to 0.2 % of its speed) and holds: the needle's
// admittance and trajectory generator re-sync to the held pose at once, so the commanded pose
// never runs away from the robot (the tracking error stays within the acceptance figure while it
// is held), the chart's reaction and the surgeon's recovery re-plan the approach from there, and
// the procedure completes.
TEST(PuncturingProcedure, ARefusedCommandMidMotionReSyncsTheCommandChainToTheHeldRobotAndTheTaskRecovers) {
  const RunResult r = runApp(withFaults("robot_slowed.lua"));
  expectTracked(r);  // while held too: the commanded pose stayed with the robot
  expectNoCommandJump(r);
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  expectInOrder(r, {"needle > root.InsertingNeedles.MoveToSkin.Approach", fault("robot_slowed.lua", 8),
                    "ISUR: e_ik_discontinuity", "NeedleAdmittance: e_resynced", "needle > root.WaitReaction",
                    "ISUR: e_ik_solved", "NeedleTrajGen: e_resynced", fault("robot_slowed.lua", 9),
                    "Surgeon: e_recover",
                    "needle > root.InsertingNeedles.MoveToSkin.Approach", "NeedlePlanner: e_plan_done",
                    "needle > root.InsertingNeedles.MoveToSkin.Descend", "NeedleMonitor: e_skin_touched",
                    "NeedleMonitor: e_target_reached", "needle > root.Done"});
  EXPECT_EQ(count(r, "ISUR: e_ik_discontinuity"), 1u) << "refused once: the re-synced command is accepted";
  EXPECT_EQ(count(r, "needle > root.WaitReaction"), 1u);
}

TEST(PuncturingProcedure, TheRoleLinterFindsNoViolationInAnyDeploymentOfTheApp) {
  for (const char* device : {"omni", "leap"}) {  // the teleoperation's master: each robot's Omni, the shared Leap
    SCOPED_TRACE(device);
    deploy::ConfiguratorOptions strict;
    strict.strict_roles = true;  // the connections made at load are refused if they break a rule
    deploy::Configurator configurator(strict);
    components::addBuiltinPackages(configurator.packages());
    script::LuaState lua;
    deploy::LuaDeployer deployer(configurator, lua);
    deployer.run("scenario = [[" + (kApp / "scenarios" / "two_needles").string() + "]]\nteleop_device = '" + device +
                     "'",
                 "=scenario");
    ASSERT_NO_THROW(deployer.runFile((kApp / "puncturing.lua").string()));
    EXPECT_TRUE(configurator.warnings().empty());
    const deploy::DeploymentSet& set = configurator.deploymentSet();
    ASSERT_EQ(set.deploymentNames().size(), 6u);  // three per robot
    for (const std::string& name : set.deploymentNames()) {
      const auto violations = deploy::lint(set.deployment(name).connections, configurator.getReferences());
      EXPECT_TRUE(violations.empty()) << name << ":\n" << deploy::toText(violations);
    }
    // needle: 3 (§4.7) and teleoperation; probe: free motion, contact and teleoperation
    EXPECT_EQ(set.configurationNames().size(), 7u);
  }
}

}  // namespace
}  // namespace cobra::run
