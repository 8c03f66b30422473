// The Puma 260 task's faults (test/faults/), each played by the runner as `cobra run apps/puma260
// --faults FILE` plays it, each ending in a defined state with its event: a drive fault and a
// working-counter mismatch (the master quick-stops the drives, Fault; the chart's SafeStop), the
// FTSens silent (the chart holds, then stops) or silent for a moment (holds, then resumes to H),
// the contact force above its limit (SafeStop), the FTSens silent from the start (the tare never
// answered: SafeStop after the chart's device timeout).

#include <gtest/gtest.h>

#include <algorithm>

#include "puma260_run.hpp"

namespace cobra::run::puma260 {
namespace {

/// The task with test/faults/`name`.lua, its run folder named after it.
RunOptions withFaults(const std::string& name) {
  RunOptions o = options("closed_form", name);
  o.faults_file = kFaults / (name + ".lua");
  return o;
}

/// The drives' measured joint speeds (rad/s) at the end of the run (the chart's SafeStop, once the
/// trajectory's stop motion has ended): all at rest.
void expectDrivesStopped(const RunOptions& o) {
  const Signals s(o.report_folder / "signals.csv");
  ASSERT_GT(s.size(), 0u);
  for (int j = 0; j < 6; ++j)
    EXPECT_LT(std::abs(s(s.size() - 1, "Puma.measJointVelocity[" + std::to_string(j) + "]")), 1e-3) << "joint " << j;
}

TEST(Puma260Faults, ADriveFaultMidMotionQuickStopsTheOthersAndTheChartStopsSafely) {
  const RunOptions o = withFaults("drive_fault");
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_NE(r.reason.find("e_drive_fault"), std::string::npos) << r.reason;
  expectInOrder(r, {"puma > root.D_StartPose", "fault " + (kFaults / "drive_fault.lua").string(),
                    "Puma: e_drive_fault", "puma > root.Stopping", "puma > root.SafeStop"});
  // The quick stop holds the robot: the kinematics solver passes the held joints on as the held
  // pose, and the trajectory's motion ends there at once instead of running on from the robot.
  expectInOrder(r, {"Puma: e_drive_fault", "TrajGen: e_resynced", "puma > root.SafeStop"});
  const auto fault = std::find(r.log.begin(), r.log.end(), "Puma: e_drive_fault");
  EXPECT_EQ(std::count(fault, r.log.end(), "TrajGen: e_motion_done"), 0) << "the motion did not run on to its end";
  EXPECT_EQ(count(r, "puma > root.H_FinalPose"), 0u);
  expectDrivesStopped(o);
}

TEST(Puma260Faults, AWorkingCounterMismatchPutsTheMasterInFaultAndTheChartStopsSafely) {
  const RunOptions o = withFaults("working_counter");
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_NE(r.reason.find("Puma: e_bus_fault"), std::string::npos) << r.reason;
  expectInOrder(r, {"puma > root.D_StartPose", "Puma: e_bus_fault", "puma > root.Stopping", "puma > root.SafeStop"});
  EXPECT_EQ(count(r, "puma > root.H_FinalPose"), 0u);
  expectDrivesStopped(o);
}

TEST(Puma260Faults, ASilentSensorMakesTheChartHoldThenStop) {
  const RunResult r = runApp(withFaults("ftsens_silent"));
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_NE(r.reason.find("FTSens: e_comm_timeout"), std::string::npos) << r.reason;
  expectInOrder(r, {"puma > root.F_FollowingSurface", "FTSens: e_comm_timeout", "puma > root.Holding",
                    "TaskSup: e_sensor_lost", "puma > root.Retreating", "puma > root.SafeStop"});
  // Held for the hold time (1 s), then stopped: in contact, after the retreat off the surface
  // (hold_test.cpp checks it).
  EXPECT_NEAR(raised(r, "TaskSup", "e_sensor_lost") - began(r, "root.Holding"), 1.0, 0.01);
  EXPECT_NEAR(began(r, "root.Retreating") - began(r, "root.Holding"), 1.0, 0.01);
}

TEST(Puma260Faults, ASensorBackWithinTheHoldTimeResumesTheNominalPathToH) {
  const RunResult r = runApp(withFaults("ftsens_dropout"));
  ASSERT_TRUE(r.completed()) << r.reason;
  expectInOrder(r, {"puma > root.F_FollowingSurface", "FTSens: e_comm_timeout", "puma > root.Holding",
                    "FTSens: e_comm_restored", "puma > root.Resuming", "puma > root.H_FinalPose"});
  EXPECT_EQ(count(r, "puma > root.SafeStop"), 0u);
}

TEST(Puma260Faults, ASensorSilentFromTheStartIsASafeStopAfterTheDeviceTimeoutNamingIt) {
  const RunResult r = runApp(withFaults("ftsens_silent_from_start"));
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_NE(r.reason.find("puma chart stopped safely in root.B_Ready.Taring: TaskSup: e_sensor_timeout"),
            std::string::npos)
      << r.reason;
  expectInOrder(r, {"puma > root.B_Ready.Taring", "TaskSup: e_sensor_timeout", "puma > root.SafeStop"});
  // The chart's device_timeout (30 s) after the tare was asked.
  EXPECT_NEAR(began(r, "root.SafeStop") - began(r, "root.B_Ready.Taring"), 30.0, 0.01);
}

TEST(Puma260Faults, AContactForceAboveTheLimitStopsTheTask) {
  const RunOptions o = withFaults("force_over_limit");
  const RunResult r = runApp(o);
  EXPECT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_NE(r.reason.find("e_force_over_limit"), std::string::npos) << r.reason;
  expectInOrder(r, {"puma > root.F_FollowingSurface", "fault " + (kFaults / "force_over_limit.lua").string(),
                    "Contact: e_force_over_limit", "puma > root.Stopping", "puma > root.SafeStop"});
  // The force did pass the limit (10 N) in the world, and the monitor said so within 20 ms (the
  // sensor's noise and the equivalent wrench's 1 ms steps). The stop ends the motion, then the tool
  // retreats off the surface without the misconfigured admittance (position_control): no force at
  // the safe stop.
  expectInOrder(r, {"Contact: e_force_over_limit", "puma > root.Retreating", "puma > root.SafeStop"});
  const Signals s(o.report_folder / "signals.csv");
  EXPECT_EQ(s(s.size() - 1, "World.contactForce"), 0.0);
  double crossed = INFINITY;
  for (std::size_t i = 0; i < s.size() && std::isinf(crossed); ++i)
    if (s(i, "World.contactForce") > 10.0) crossed = s.time(i);
  const double detected = raised(r, "Contact", "e_force_over_limit");
  ASSERT_LT(crossed, INFINITY);
  EXPECT_LT(detected - crossed, 0.02) << "crossed at " << crossed << " s, detected at " << detected << " s";
  EXPECT_GT(detected - crossed, -0.02) << "crossed at " << crossed << " s, detected at " << detected << " s";
}

}  // namespace
}  // namespace cobra::run::puma260
