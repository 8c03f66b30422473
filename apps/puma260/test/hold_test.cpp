// A safe stop with the tool on the surface (charts/puma260_task.lua, Retreating): the admittance in
// Exception or the FTSens silent, the tool retreats T.retreat up along base z on the
// position_control path, slowly, following its set-point; the IK slowed to 0.2 % of its joint
// speeds refuses that retreat, and the master's joint-space move to ready lifts the tool instead.
// Then it holds off the surface: in the second after the safe stop (the runner steps on for
// it, RunOptions::watch_after_end, as `cobra faults matrix` does) it moves less than kStill and the
// world's contact force is zero. Pressed on the surface instead, a position hold hunts by 0.6-2 mm
// (stick-slip of the wrist: the fault matrix's declared gaps before the retreat).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "puma260_run.hpp"

namespace cobra::run::puma260 {
namespace {

constexpr double kRetreat = 0.003;   // m: T.retreat of deployment/task_geometry.lua
constexpr double kStill = 0.05e-3;   // m: the tool's largest motion in the second after the safe stop
constexpr double kReadyRise = 0.141;  // m: the ready position's tool (z = 0.25 m) above the stop's (about 0.109 m)
constexpr double kStillReady = 0.2e-3;  // m: the same after the master's move to ready (it settles)
// m: measured tool from the retreat's set-point while it runs (largest while the ball unloads and
// leaves the surface, the first 0.3 mm)
constexpr double kTracking = 0.8e-3;

/// The largest distance (m) from the point (x, y, z) of port `pose` at row `from` to the same
/// point at rows from..to.
double largestMotion(const Signals& s, const std::string& pose, std::size_t from, std::size_t to) {
  double worst = 0.0;
  for (std::size_t i = from; i <= to; ++i)
    worst = std::max(worst, std::hypot(s(i, pose + ".x") - s(from, pose + ".x"), s(i, pose + ".y") - s(from, pose + ".y"),
                                       s(i, pose + ".z") - s(from, pose + ".z")));
  return worst;
}

/// The task with test/faults/`name`.lua (a fault while in F), watched for 1 s after its outcome.
/// `ready`: the IK refuses the retreat, so the master's joint-space move to the ready position
/// (root.ToReady) takes the tool off the surface instead: up by 0.14 m, then held within kStillReady.
void expectRetreatedAndHolding(const std::string& name, const std::string& failure, bool ready = false) {
  RunOptions o = options("closed_form", "hold_" + name);
  o.faults_file = kFaults / (name + ".lua");
  o.watch_after_end = 1.0;
  const RunResult r = runApp(o);
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_NE(r.reason.find(failure), std::string::npos) << r.reason;
  if (ready)
    expectInOrder(r, {"puma > root.F_FollowingSurface", failure, "puma > root.Retreating",
                      "deployment > position_control", "Kin: e_ik_discontinuity", "puma > root.ToReady",
                      "Puma: e_ready_reached", "puma > root.SafeStop"});
  else
    expectInOrder(r, {"puma > root.F_FollowingSurface", failure, "puma > root.Retreating",
                      "deployment > position_control", "puma > root.Retreating.Withdrawing", "TrajGen: e_motion_done",
                      "puma > root.SafeStop"});
  const double retreat = began(r, ready ? "root.ToReady" : "root.Retreating.Withdrawing"), stop = began(r, "root.SafeStop");
  ASSERT_LT(stop, INFINITY);

  const Signals s(o.report_folder / "signals.csv");
  ASSERT_GT(s.size(), 0u);
  std::size_t first = s.size(), at_stop = s.size();  // rows: the retreat's start, the safe stop
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (first == s.size() && s.time(i) >= retreat) first = i;
    if (at_stop == s.size() && s.time(i) >= stop) at_stop = i;
  }
  const std::size_t last = s.size() - 1;
  ASSERT_LT(at_stop, last);
  // Recorded at 100 Hz: the last row is 0.99 s after the first row at or after the safe stop (within rounding).
  ASSERT_GE(s.time(last) - s.time(at_stop), 0.99 - 1e-9) << "the second after the safe stop is recorded";
  // In contact when the retreat began; off the surface by the retreat's height at the safe stop.
  EXPECT_GT(s(first, "World.contactForce"), 1.0);
  const double up = s(at_stop, "World.toolPose.z") - s(first, "World.toolPose.z");
  EXPECT_NEAR(up, ready ? kReadyRise : kRetreat, ready ? 5e-3 : 0.3e-3);
  // The retreat: the measured tool followed its set-point (position_control: TrajGen's pose is the
  // command). The move to ready: no Cartesian command; the tool never pressed harder than at the stop.
  double tracking = 0.0, pressed = 0.0;
  for (std::size_t i = first; i <= at_stop; ++i) {
    if (!ready)
      tracking = std::max(tracking, std::hypot(s(i, "Kin.cartPose.x") - s(i, "TrajGen.desCartPose_1.x"),
                                               s(i, "Kin.cartPose.y") - s(i, "TrajGen.desCartPose_1.y"),
                                               s(i, "Kin.cartPose.z") - s(i, "TrajGen.desCartPose_1.z")));
    pressed = std::max(pressed, s(i, "World.contactForce"));
  }
  EXPECT_LT(tracking, kTracking);
  EXPECT_LT(pressed, s(first, "World.contactForce") + 1.0);  // N: the stop's force and the sensor's noise
  // Held still, off the surface, in the second after the safe stop.
  const double moved = largestMotion(s, "Kin.cartPose", at_stop, last);
  const double moved_true = largestMotion(s, "World.toolPose", at_stop, last);
  double force = 0.0;
  for (std::size_t i = at_stop; i <= last; ++i) force = std::max(force, s(i, "World.contactForce"));
  EXPECT_LT(moved, ready ? kStillReady : kStill);
  EXPECT_LT(moved_true, ready ? kStillReady : kStill);
  EXPECT_EQ(force, 0.0);
  std::printf("%s: %s %.3f s from %.3f s, %.2f mm up, tracking %.3f mm, force at most %.3f N; after the safe stop "
              "the tool moved %.4f mm (measured) %.4f mm (true), contact force at most %.3f N\n",
              name.c_str(), ready ? "move to ready" : "retreat", stop - retreat, retreat, up * 1e3, tracking * 1e3, pressed,
              moved * 1e3, moved_true * 1e3, force);
}

TEST(Puma260Hold, TheAdmittanceInExceptionInContactRetreatsWithoutItAndHolds) {
  expectRetreatedAndHolding("admittance_exception", "Admittance: e_component_error");
}

TEST(Puma260Hold, TheSensorSilentInContactRetreatsAfterTheHoldTimeAndHolds) {
  expectRetreatedAndHolding("ftsens_silent", "FTSens: e_comm_timeout");
}

TEST(Puma260Hold, TheIkSlowedInContactLeavesTheSurfaceWithoutItAndHolds) {
  expectRetreatedAndHolding("ik_slowed", "Kin: e_ik_discontinuity", true);
}

}  // namespace
}  // namespace cobra::run::puma260
