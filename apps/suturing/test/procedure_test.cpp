// The suturing task end to end in simulation through the runner's API (cobra/run/runner.hpp, what
// `cobra run apps/suturing` does): suturing.lua — the two-armed I-SUR, the wound, the controller
// with its three supervisors, three deployments and two configurations — on the lockstep clock,
// nominal on both scenarios and with the faults files of test/faults/ (each ending in a defined
// state with its event), the teleoperation with the Leap Motion and with the Omnis.

#include "cobra/run/runner.hpp"

#include <gtest/gtest.h>

#include "procedure_expectations.hpp"

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/test_support.hpp"

#include <kdl/frames.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

namespace cobra::run {
namespace {

using namespace suturing_testing;

/// When the chart first entered `state` (s), -1 when it never did.
double entered(const RunResult& r, const std::string& state) {
  for (const report::EventRecord& e : r.events)
    if (e.state == state) return e.time;
  return -1.0;
}

/// How far `port`'s position (a KDL.Frame column of signals.csv) moves from its first record at or
/// after `from` (s) over the records after it [mm]; `seconds` is the span recorded from `from` (s).
double movedSince(const Signals& signals, const std::string& port, double from, double& seconds) {
  const std::size_t t = signals.column("time");
  const std::size_t x = signals.column(port + ".x");
  const std::vector<double>* start = nullptr;
  double worst = 0.0;
  seconds = 0.0;
  for (const auto& row : signals.rows) {
    if (row[t] < from - 1e-9) continue;
    if (start == nullptr) start = &row;
    worst = std::max(worst, std::hypot(row[x] - (*start)[x], row[x + 1] - (*start)[x + 1], row[x + 2] - (*start)[x + 2]));
    seconds = row[t] - from;
  }
  return worst * 1000.0;
}

/// Both tools hold over the second after the chart entered `state` (the run watched on, see
/// RunOptions::watch_after_end): neither measured tip moves more than 0.25 mm from where it was
/// then (the fault matrix holds a task to 0.5 mm; the RestMonitor answers at 0.5 mm/s).
void expectBothToolsHoldAfter(const RunResult& r, const Signals& signals, const std::string& state) {
  const double from = entered(r, state);
  ASSERT_GE(from, 0.0) << "the chart never entered " << state;
  for (const std::string tool : {"ISUR.measRightCartPose", "ISUR.measLeftCartPose"}) {
    double seconds = 0.0;
    const double moved = movedSince(signals, tool, from, seconds);
    EXPECT_GT(seconds, 0.95) << tool << ": the second after " << state << " was not recorded";
    EXPECT_LT(moved, 0.25) << tool << " moved after " << state << " (mm)";
    std::printf("%s: %.3f mm in the %.2f s after %s at %.3f s\n", tool.c_str(), moved, seconds, state.c_str(), from);
  }
}

/// Done means at rest (expectBothToolsHoldAfter root.Done). Without Finishing the stick and the
/// Endo Stitch, let go of the thread's pull, moved 3.4 and 2.2 mm.
void expectAtRestOnceDone(const RunResult& r, const Signals& signals) { expectBothToolsHoldAfter(r, signals, "root.Done"); }

TEST(SuturingProcedure, TheStraightCutIsClosedWithFourStitchesThroughThePhasesAToH) {
  RunOptions o = options("straight_cut");
  o.watch_after_end = 1.0;  // s: the run steps on after Done, recorded (the tools must hold)
  o.report_folder = std::filesystem::temp_directory_path() / ("cobra_suturing_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  expectSutured(r, 4);
  // §5.6's phases for the first stitch: A at the initial poses; B over the wound (planned); C
  // inside it; D at the edge, the stitch applied; E the thread pulled (contact); F hooked; G pushed
  // aside; H over the wound again for the second half.
  const std::string s = "suture > root.AutonomousMode.";
  expectInOrder(r, {s + "ApplyRightStitch.MoveOverWound", "suture deployment > suturing_autonomous_planning",
                    s + "ApplyRightStitch.MoveInsideWound", s + "ApplyRightStitch.MoveToWoundEdge",
                    s + "ApplyRightStitch.ApplyStitch", "ISUR: e_endo_stitch_actuated", "Patient: e_stitch_applied",
                    s + "ApplyRightStitch.DisengageNeedle", s + "PullThread", "configuration > suturing_contact",
                    s + "HookThread", "Patient: e_thread_hooked", s + "PushThread",
                    s + "ApplyLeftStitch.MoveOverWound", s + "ApplyLeftStitch.ApplyStitch", "Patient: e_stitch_applied",
                    s + "PullThread", s + "GetStitchTargetPose", "suture > root.Finishing", "ArmsRest: e_at_rest",
                    "suture > root.Done"});
  EXPECT_EQ(count(r, "Patient: e_thread_hooked"), 8u);
  expectCaughtOnlyByTheHookingMotion(r);
  EXPECT_EQ(count(r, "Patient: e_thread_broken"), 0u);
  // The measured clearance stays above the planner's threshold the whole run long, the Endo
  // Stitch's contact with the phantom (a primitive contact of the scene) left out and reported
  // apart: it does reach into the phantom, at every half-stitch.
  EXPECT_GT(r.clearance.seconds_sampled, 50.0);
  EXPECT_GT(r.clearance.worst, r.clearance.threshold) << r.clearance.worst_at << " s, " << r.clearance.worst_state;
  EXPECT_EQ(r.clearance.unreachable, 0);
  ASSERT_EQ(r.clearance.contacts.size(), 1u);
  EXPECT_EQ(r.clearance.contacts[0].first, "Endo Stitch in the wound");
  EXPECT_EQ(r.clearance.contacts[0].second, 0.0);
  // The admittances' rebase threshold (0.1 m/s, 1 rad/s: controller.lua) catches each motion's
  // start at the measured pose and nothing of the motions themselves.
  std::vector<double> starts;
  for (const report::EventRecord& e : r.events)
    if (e.event.rfind("e_moving", 0) == 0) starts.push_back(e.time);
  for (const report::EventRecord& e : r.events) {
    if (e.event.rfind("e_reference_jump", 0) != 0) continue;
    EXPECT_TRUE(std::any_of(starts.begin(), starts.end(), [&](double t) { return e.time >= t && e.time - t <= 0.003; }))
        << e.source << " at " << e.time << " s in " << e.state;
  }
  const Signals signals(o.report_folder);
  expectTheThreadsPullOnTheStick(r, signals);
  expectTheTanksHoldTheWorkAgainstTheThread(r, signals);
  expectAtRestOnceDone(r, signals);
  std::filesystem::remove_all(o.report_folder);
}

TEST(SuturingProcedure, TheSlantedCutIsClosedWithThreeStitches) {
  const RunResult r = runApp(options("slanted_cut"));
  expectSutured(r, 3);
  EXPECT_GT(r.clearance.worst, r.clearance.threshold) << r.clearance.worst_at << " s, " << r.clearance.worst_state;
}

// Slanted the other way: the platform turns the other way from stitch to stitch.
TEST(SuturingProcedure, TheCutSlantedPositivelyIsClosedWithThreeStitches) {
  const RunResult r = runApp(options("slanted_cut_positive"));
  expectSutured(r, 3);
  EXPECT_GT(r.clearance.worst, r.clearance.threshold) << r.clearance.worst_at << " s, " << r.clearance.worst_state;
  expectCaughtOnlyByTheHookingMotion(r);
}

// Each stitch at its own direction (+7.4, 0, -7.4 degrees at the stitches): the stick's goal before
// each stitch follows the stitch, so the turning platform does not fold the arms together.
TEST(SuturingProcedure, TheCurvedCutIsClosedWithThreeStitches) {
  const RunResult r = runApp(options("curved_cut"));
  expectSutured(r, 3);
  EXPECT_GT(r.clearance.worst, r.clearance.threshold) << r.clearance.worst_at << " s, " << r.clearance.worst_state;
  expectCaughtOnlyByTheHookingMotion(r);
}

/// The surgeon takes over mid-stitch: the motion stops, the haptic device's deployment starts, the
/// teleoperation runs, and the interrupted motion resumes; the command never jumps.
void expectTakeOver(const std::string& device) {
  const RunResult r = runApp(withFaults("take_over.lua", device));
  expectSutured(r, 4);
  expectInOrder(r, {"suture > root.AutonomousMode.ApplyRightStitch.MoveToWoundEdge", "Surgeon: e_take_over",
                    "suture > root.TeleoperatedMode.StoppingMotion", "suture > root.TeleoperatedMode.InitHapticDevice",
                    "suture deployment > suturing_teleoperated", "suture > root.TeleoperatedMode.TeleoperationActive",
                    "Surgeon: e_teleop_done", "suture > root.AutonomousMode.ApplyRightStitch.MoveToWoundEdge"});
  for (const TrackingFigures& arm : r.tracking)
    EXPECT_LT(arm.max_command_step, 1e-3) << arm.robot << " at " << arm.max_command_step_at << " s";
}

TEST(SuturingProcedure, ASurgeonTakingOverMidStitchWithTheLeapMotionStopsTeleoperatesAndResumes) {
  expectTakeOver("leap");
}

TEST(SuturingProcedure, ASurgeonTakingOverMidStitchWithTheOmnisStopsTeleoperatesAndResumes) {
  expectTakeOver("omni");
}

TEST(SuturingProcedure, ATeleoperationSetPointIntoThePhantomIsHeldByTheStateValidator) {
  RunOptions o = withFaults("teleop_into_collision.lua", "omni");
  o.report_folder = std::filesystem::temp_directory_path() / ("cobra_suturing_teleop_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  expectSutured(r, 4);  // the procedure goes on after the teleoperation
  expectInOrder(r, {"suture > root.TeleoperatedMode.TeleoperationActive", "Validator: e_state_invalid",
                    "Validator: e_state_valid", "Surgeon: e_teleop_done", "suture > root.Done"});
  // The coupling dragged the Endo Stitch's admittance after the sinking stylus, step by step: the
  // robot never had to refuse a set-point as a jump.
  EXPECT_EQ(count(r, "ISUR: e_ik_discontinuity"), 0u);
  // The last valid set-points were kept: the arms never came near the phantom.
  EXPECT_GT(r.clearance.worst, r.clearance.threshold) << r.clearance.worst_at << " s";
  // The validator holding: the Endo Stitch's admittance re-synced to the held set-point, so its
  // commanded pose stayed with the robot instead of following the stylus into the phantom.
  expectInOrder(r, {"Validator: e_state_invalid", "RightAdmittance: e_resynced", "Validator: e_state_valid"});
  const Signals s(o.report_folder);
  double worst = 0.0;
  for (const auto& row : s.rows) {
    double squared = 0.0;
    for (const char* axis : {".x", ".y", ".z"}) {
      const double d = row[s.column(std::string("RightAdmittance.admPose") + axis)] -
                       row[s.column(std::string("ISUR.measRightCartPose") + axis)];
      squared += d * d;
    }
    worst = std::max(worst, std::sqrt(squared));
  }
  std::printf("worst distance between the Endo Stitch's commanded and measured tip: %.2f mm\n", 1000.0 * worst);
  EXPECT_LT(worst, 0.005) << "m: the commanded pose ran away from the held robot";
  for (const TrackingFigures& arm : r.tracking)
    EXPECT_LT(arm.max_command_step, 1e-3) << arm.robot << " at " << arm.max_command_step_at << " s";
}

TEST(SuturingProcedure, AThreadPulledPastItsBreakingTensionBreaksAndTheChartStopsSafely) {
  const RunResult r = runApp(withFaults("thread_over_tension.lua"));
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  expectInOrder(r, {"suture > root.AutonomousMode.PullThread", "Patient: e_thread_broken", "suture > root.SafeStop",
                    "suture safe stop"});
  EXPECT_EQ(r.value("half-stitches applied").values.size(), 1u);
}

TEST(SuturingProcedure, APlannerFailureIsAReactionAndTheRetryAfterRecoverySucceeds) {
  const RunResult r = runApp(withFaults("planner_fails_once.lua"));
  expectSutured(r, 4);
  expectInOrder(r, {"suture > root.AutonomousMode.ApplyRightStitch.MoveOverWound", "SuturePlanner: e_plan_failed",
                    "suture > root.WaitReaction", "Surgeon: e_recover",
                    "suture > root.AutonomousMode.ApplyRightStitch.MoveOverWound"});
}

TEST(SuturingProcedure, ASurgeonWhoNeverReactsEndsTheProcedureInTheSafeStopNamingTheTimeout) {
  const RunResult r = runApp(withFaults("surgeon_never_reacts.lua"));
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_CONTAINS(r.reason, "suture chart stopped safely in root.WaitReaction: TaskSup: e_reaction_timeout at ");
  expectInOrder(r, {"SuturePlanner: e_plan_failed", "suture > root.WaitReaction", "TaskSup: e_reaction_timeout",
                    "suture > root.SafeStop"});
  EXPECT_EQ(count(r, "Surgeon: e_recover"), 0u);
}

/// A safe stop early in the first motion: the Endo Stitch's admittance fails 0.3 s into
/// ApplyRightStitch.MoveOverWound (`faults`: as the fault matrix's over_wound cells), with both
/// arms moving at about 19 mm/s along the planned pair of paths; the chart stops safely at once.
/// The failed admittance holds the Endo Stitch (its admPose frozen) and tells the trajectory
/// generator (heldRefPose), which holds the stick too: both tools hold over the second after the
/// safe stop (before, the stick ran on through the generator's 0.2 s stop motion, 2.0 mm), and the
/// arms tracked their commands until then.
void expectBothArmsHoldAfterAnEarlySafeStop(const std::string& faults, const std::string& event) {
  RunOptions o = withFaults(faults);
  o.watch_after_end = 1.0;  // s: the run steps on after the safe stop, recorded (the tools must hold)
  o.report_folder = std::filesystem::temp_directory_path() / ("cobra_suturing_stop_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  expectInOrder(r, {"suture > root.AutonomousMode.ApplyRightStitch.MoveOverWound", event, "suture > root.SafeStop",
                    "suture safe stop"});
  const double stopped = entered(r, "root.SafeStop");
  EXPECT_NEAR(stopped, 0.3, 0.01) << "s: the safe stop early in the first motion";
  expectTracked(r, 0.25);  // s: the first motion's 0.3 s at least
  const Signals signals(o.report_folder);
  // The stick was moving when it stopped (the hold below is not a robot that never moved).
  double seconds = 0.0;
  EXPECT_GT(movedSince(signals, "ISUR.measLeftCartPose", stopped - 0.1, seconds), 1.0) << "mm in the 0.1 s before";
  expectBothToolsHoldAfter(r, signals, "root.SafeStop");
  std::filesystem::remove_all(o.report_folder);
}

TEST(SuturingProcedure, TheAdmittanceFailingEarlyInTheFirstMotionStopsSafelyAndBothArmsHold) {
  expectBothArmsHoldAfterAnEarlySafeStop("admittance_fails_over_wound.lua", "RightAdmittance: e_component_error");
}

TEST(SuturingProcedure, ANonFiniteWrenchEarlyInTheFirstMotionStopsSafelyAndBothArmsHold) {
  expectBothArmsHoldAfterAnEarlySafeStop("nan_wrench_over_wound.lua", "RightAdmittance: e_input_not_finite");
}

/// The suturing application loaded as `cobra run` loads it, on the lockstep clock, with its task
/// chart wrapped: the entry of ApplyRightStitch.MoveOverWound.Moving starts the motion, then runs
/// `fault` (Lua). The task Supervisor must go to Exception naming the wrapper's line, and its
/// chart's exceptionHook stop the motion: the Endo Stitch's commanded pose stops changing.
void expectTheArmsHoldAfter(const std::string& fault, const std::string& expected) {
  using namespace std::chrono_literals;
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.run("teleop_device = 'leap'", "=device");
  deployer.runFile((kApp / "suturing.lua").string());
  const std::string charts = (kApp / "charts").string();
  const std::string wrapper = ::cobra::test_support::scratchPath("suturing_broken_" + std::to_string(fault.size()) + ".lua").string();
  std::ofstream(wrapper) << "package.path = '" << charts << "/?.lua;' .. package.path\n"
                         << "local chart = dofile('" << charts << "/suturing.lua')\n"
                         << "local moving = chart.AutonomousMode.ApplyRightStitch.MoveOverWound.Moving\n"
                         << "local start = moving.entry\n"
                         << "moving.entry = function(...)\n"
                         << "  start(...)\n"
                         << "  " << fault << "\n"
                         << "end\n"
                         << "return chart\n";
  deployer.run("stopComponents({'TaskSup'}) cleanupComponents({'TaskSup'}) TaskSup.fsm_path = [[" + wrapper +
                   "]] configureComponents({'TaskSup'}) startComponents({'TaskSup'})",
               "=wrap the chart");
  core::Component& sup = configurator.getReferences().get("TaskSup");
  core::InputPort<KDL::Frame> commanded{"commanded", "", "m"}, measured{"measured", "", "m"};
  core::connectPorts(configurator.getReferences().get("RightAdmittance").port("admPose"), commanded);
  core::connectPorts(configurator.getReferences().get("ISUR").port("measRightCartPose"), measured);
  double t = 0.0;
  for (; t < 60.0 && sup.state() == core::State::Running; t += 0.01) configurator.clock().advance(10ms);
  ASSERT_EQ(sup.state(), core::State::Exception) << "at " << t << " s";
  EXPECT_EQ(sup.lastError(), "component 'TaskSup': updateHook threw: entry of "
                             "root.AutonomousMode.ApplyRightStitch.MoveOverWound.Moving failed: " +
                                 wrapper + ":7: " + expected);
  configurator.clock().advance(600ms);  // past the trajectory generator's stop motion
  KDL::Frame commanded_then, measured_then, commanded_later, measured_later;
  const core::FlowStatus commanded_first = commanded.read(commanded_then);
  ASSERT_NE(measured.read(measured_then), core::FlowStatus::NoData);
  configurator.clock().advance(2s);
  const core::FlowStatus commanded_second = commanded.read(commanded_later);
  ASSERT_NE(measured.read(measured_later), core::FlowStatus::NoData);
  // The motion was stopped as it began: the admittance was never commanded to move (no sample),
  // or holds its last command; the arm stays where it is.
  EXPECT_EQ(commanded_first == core::FlowStatus::NoData, commanded_second == core::FlowStatus::NoData);
  if (commanded_first != core::FlowStatus::NoData) {
    EXPECT_TRUE(KDL::Equal(commanded_then, commanded_later, 1e-9));
  }
  EXPECT_TRUE(KDL::Equal(measured_then, measured_later, 1e-6))
      << "moved by " << (measured_later.p - measured_then.p).Norm() << " m";
}

TEST(SuturingProcedure, AnEndlessLoopInTheTaskChartIsCutAndTheArmsHold) {
  expectTheArmsHoldAfter("while true do end",
                         "component 'TaskSup' ran past its budget of 0.005 s of CPU time; raise its lua_budget "
                         "property if the chart needs that long");
}

TEST(SuturingProcedure, ALuaErrorInTheTaskChartIsAnExceptionAndTheArmsHold) {
  expectTheArmsHoldAfter("stopp()", "attempt to call a nil value (global 'stopp')");
}

/// Loaded with the strict role rules (a connection that breaks one is refused at load), with
/// either haptic device: no violation in any deployment, both configurations there.
void expectNoRoleViolation(const std::string& device) {
  deploy::ConfiguratorOptions strict;
  strict.strict_roles = true;
  deploy::Configurator configurator(strict);
  components::addBuiltinPackages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.run("teleop_device = '" + device + "'", "=device");
  ASSERT_NO_THROW(deployer.runFile((kApp / "suturing.lua").string()));
  EXPECT_TRUE(configurator.warnings().empty());
  const deploy::DeploymentSet& set = configurator.deploymentSet();
  ASSERT_EQ(set.deploymentNames().size(), 3u);  // §5.5.1
  for (const std::string& name : set.deploymentNames()) {
    const auto violations = deploy::lint(set.deployment(name).connections, configurator.getReferences());
    EXPECT_TRUE(violations.empty()) << name << ":\n" << deploy::toText(violations);
  }
  EXPECT_EQ(set.configurationNames().size(), 3u);  // §5.5.2: free motion, contact; and teleoperation
}

TEST(SuturingProcedure, TheRoleLinterFindsNoViolationInAnyDeploymentWithEitherDevice) {
  expectNoRoleViolation("leap");
  expectNoRoleViolation("omni");
}

}  // namespace
}  // namespace cobra::run
