// The suturing task's teleoperation through the two-layer coupling (thesis §4.5.4 in the
// deployment of §5.5.1), end to end in simulation (the runner's API, lockstep clock): the surgeon
// takes over while the Endo Stitch pulls the thread, with the Omnis and with the Leap Motion,
// without and with an impaired link (100 ms delay, 10 % loss). Asserted on the recorded signals:
// nothing jumps at the switches, the master feels the thread's pull, the Endo Stitch follows the
// device's motion, the coupling's tanks stay above their minimum, the clearance holds; and the
// procedure goes on to the end.

#include <gtest/gtest.h>

#include "procedure_expectations.hpp"

#include "cobra/run/runner.hpp"

#include <kdl/frames.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

namespace cobra::run {
namespace {

using namespace suturing_testing;

/// Time (s) of the first event `event` from `source`, NaN when there is none.
double timeOf(const RunResult& r, const std::string& source, const std::string& event) {
  for (const report::EventRecord& e : r.events)
    if (e.source == source && e.event.rfind(event, 0) == 0) return e.time;
  return std::nan("");
}

KDL::Vector position(const Signals& s, const std::vector<double>& row, const std::string& frame) {
  const std::size_t x = s.column(frame + ".x");
  return {row[x], row[x + 1], row[x + 2]};
}

KDL::Rotation orientation(const Signals& s, const std::vector<double>& row, const std::string& frame) {
  const std::size_t q = s.column(frame + ".qx");
  return KDL::Rotation::Quaternion(row[q], row[q + 1], row[q + 2], row[q + 3]);
}

/// The row recorded at or just after `time` (s).
const std::vector<double>& rowAt(const Signals& s, double time) {
  for (const auto& row : s.rows)
    if (row[0] >= time - 1e-9) return row;
  return s.rows.back();
}

struct Figures {
  double force_along_pull = 0.0;  // N: the master's force along the thread's pull on the tool, mean
  double tension = 0.0;           // N: the thread's tension meanwhile, mean
  double follow_error = 0.0;      // m: the Endo Stitch's motion minus the device's (mapped) motion
  double device_motion = 0.0;     // m
  double lowest_tank = 1e9;       // J: either coupling tank, over the teleoperation
  double switch_step = 0.0;       // m: the commanded pose's largest change across a switch
  double switch_turn = 0.0;       // rad
  double orientation_error = 0.0;  // rad: the Endo Stitch's against the device's (mapped), at the end
};

/// The take-over while pulling (take_over_pulling_<device>.lua), with `link` the Lua table of the
/// coupling's link impairment ("" = none).
Figures takeOverWhilePulling(const std::string& device, const std::string& link) {
  RunOptions o = withFaults("take_over_pulling_" + device + ".lua", device);
  if (!link.empty()) o.before_lua += "\nteleop_link = " + link;
  // Recorded beside the application's ports: the device's motion mapped onto the tool (the
  // master), the force the master feels (the Omni: what its side's Passivity layer renders; the
  // Leap renders none: the master's wrench as it arrives over the link, what a haptic device would
  // be given), the two sides' tanks, the thread's wrench on the tool. (Last: a port without data
  // yet is one empty cell, whatever its width.)
  const std::string felt_port = device == "leap" ? "RightLink.linkedSlaveWrench" : "RightMasterPassivity.force";
  o.extra_lua = "for _, p in ipairs({ 'Patient.toolWrench', 'RightMasterPassivity.tankEnergy', "
                "'RightSlavePassivity.tankEnergy', '" + felt_port + "', 'RightClutch.desPose' }) do "
                "run.record.ports[#run.record.ports + 1] = p end";
  o.report_folder = std::filesystem::temp_directory_path() /
                    ("cobra_suturing_pull_" + device + (link.empty() ? "" : "_link") + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  Figures f;
  expectSutured(r, 4);
  if (::testing::Test::HasFatalFailure()) return f;
  expectInOrder(r, {"suture > root.AutonomousMode.PullThread", "Surgeon: e_take_over",
                    "suture > root.TeleoperatedMode.StoppingMotion", "suture > root.TeleoperatedMode.InitHapticDevice",
                    "suture deployment > suturing_teleoperated", "suture > root.TeleoperatedMode.TeleoperationActive",
                    "Surgeon: e_teleop_done", "suture > root.AutonomousMode.PullThread"});
  EXPECT_GT(r.clearance.worst, r.clearance.threshold) << r.clearance.worst_at << " s, " << r.clearance.worst_state;
  for (const TrackingFigures& arm : r.tracking)
    EXPECT_LT(arm.max_command_step, 1e-3) << arm.robot << " at " << arm.max_command_step_at << " s";

  const double active = timeOf(r, "TaskSup", "e_teleoperation_active");
  const double done = timeOf(r, "Surgeon", "e_teleop_done");
  const double moved = active + 1.0;  // the fault file moves the hand 1 s into the teleoperation
  if (std::isnan(active) || std::isnan(done)) {
    ADD_FAILURE() << "the teleoperation never became active or never ended";
    return {};
  }
  const Signals s(o.report_folder);
  // The switches: the commanded pose (the Endo Stitch's admittance) across each, one recorded
  // period (10 ms) either side.
  for (const double t : {active, done}) {
    const auto& before = rowAt(s, t - 0.011);
    const auto& after = rowAt(s, t + 0.011);
    f.switch_step = std::max(f.switch_step, (position(s, after, "RightAdmittance.admPose") -
                                             position(s, before, "RightAdmittance.admPose")).Norm());
    f.switch_turn = std::max(f.switch_turn, (orientation(s, after, "RightAdmittance.admPose") *
                                             orientation(s, before, "RightAdmittance.admPose").Inverse()).GetRot().Norm());
  }
  // The thread's pull, felt: from 0.3 s into the teleoperation (the link's delay, the coupling
  // settled) to the hand's motion, the force the coupling gives the master along the thread's
  // pull on the tool (Patient.toolWrench, world axes).
  int n = 0;
  for (const auto& row : s.rows) {
    if (row[0] < active + 0.3 || row[0] >= moved) continue;
    const std::size_t w = s.column("Patient.toolWrench.fx"), m = s.column(felt_port + ".fx");
    const KDL::Vector pull(row[w], row[w + 1], row[w + 2]), felt(row[m], row[m + 1], row[m + 2]);
    if (pull.Norm() < 1e-9) continue;
    f.force_along_pull += KDL::dot(felt, pull / pull.Norm());
    f.tension += row[s.column("Patient.threadTension")];
    ++n;
  }
  EXPECT_GT(n, 20);
  if (n > 0) {
    f.force_along_pull /= n;
    f.tension /= n;
  }
  for (const auto& row : s.rows) {
    if (row[0] < active || row[0] > done) continue;
    f.lowest_tank = std::min({f.lowest_tank, row[s.column("RightMasterPassivity.tankEnergy")],
                              row[s.column("RightSlavePassivity.tankEnergy")]});
  }
  // The device's motion (mapped onto the tool by the clutch) from just before the hand moved to
  // just before it turns back (2.9 s into the teleoperation: moved, turned, settled), against the
  // Endo Stitch's measured motion.
  const auto& start = rowAt(s, moved - 0.02);
  const auto& end = rowAt(s, active + 2.9);
  const KDL::Vector device_motion =
      position(s, end, "RightClutch.desPose") - position(s, start, "RightClutch.desPose");
  const KDL::Vector tool_motion =
      position(s, end, "ISUR.measRightCartPose") - position(s, start, "ISUR.measRightCartPose");
  f.device_motion = device_motion.Norm();
  f.follow_error = (tool_motion - device_motion).Norm();
  f.orientation_error = (orientation(s, end, "RightClutch.desPose") *
                         orientation(s, end, "ISUR.measRightCartPose").Inverse()).GetRot().Norm();
  std::printf("%s%s: master force along the pull %.2f N (tension %.2f N); device moved %.1f mm, the Endo Stitch "
              "%.2f mm off that; lowest tank %.2f J; at the switches %.3f mm, %.3f deg; orientation against the "
              "device %.2f deg\n",
              device.c_str(), link.empty() ? "" : " (impaired link)", f.force_along_pull, f.tension,
              1000.0 * f.device_motion, 1000.0 * f.follow_error, f.lowest_tank, 1000.0 * f.switch_step,
              f.switch_turn * 180.0 / M_PI, f.orientation_error * 180.0 / M_PI);
  std::filesystem::remove_all(o.report_folder);
  return f;
}

/// What every take-over while pulling must show; `follow` (m): the Endo Stitch's motion may miss
/// the device's by at most this; `felt` (N): the master's least force along the thread's pull.
void expectCoupled(const Figures& f, double follow, double felt) {
  EXPECT_GT(f.tension, 0.5);            // N: the thread was tensioned while felt
  EXPECT_GT(f.force_along_pull, felt);  // N: the master is pulled the way the thread pulls the tool
  EXPECT_GT(f.device_motion, 0.005);    // m: the surgeon's 8.5 mm motion (the device gives way to the pull) reached the tool's side
  EXPECT_LT(f.follow_error, follow);
  EXPECT_GT(f.lowest_tank, 1.0);        // J: above the tanks' minimum ε
  EXPECT_LT(f.switch_step, 1e-3);       // m
  EXPECT_LT(f.switch_turn, M_PI / 180.0);
  EXPECT_LT(f.orientation_error, M_PI / 180.0);  // the device's 10 degree turn, followed within 1
}

TEST(SuturingTeleoperation, TheOmniFeelsTheThreadsPullAndTheEndoStitchFollowsIt) {
  expectCoupled(takeOverWhilePulling("omni", ""), 0.003, 0.5);
}

TEST(SuturingTeleoperation, TheLeapMotionsHandDrivesTheEndoStitchWhileTheCouplingHoldsThePull) {
  expectCoupled(takeOverWhilePulling("leap", ""), 0.003, 0.5);
}

// 100 ms one way and 10 % of the packets lost on each arm's link, both directions: the coupling
// at 300 N/m (controller.lua), the tool gives more way to the thread, the master feels less.
TEST(SuturingTeleoperation, WithADelayedLossyLinkTheTakeOverStillCompletes) {
  expectCoupled(takeOverWhilePulling("omni", "{ delay = 0.1, loss = 0.1, seed = 3 }"), 0.0045, 0.2);
}

TEST(SuturingTeleoperation, WithADelayedLossyLinkTheLeapTakeOverStillCompletes) {
  expectCoupled(takeOverWhilePulling("leap", "{ delay = 0.1, loss = 0.1, seed = 3 }"), 0.0045, 0.2);
}

}  // namespace
}  // namespace cobra::run
