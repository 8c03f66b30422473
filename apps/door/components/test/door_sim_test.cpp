// The door example's simulated world: what the task chart relies on happens, and only then.
#include "cobra/components/door/door_sim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct World {
  DoorSim door{"Door"};
  core::LockstepClock clock;
  core::OutputPort<double> arm{"arm", "", "m"}, grip{"grip", "", "1"}, torque{"torque", "", "N·m"}, pull{"pull", "", "N"};
  core::InputPort<double> arm_position{"p", "", "m"}, gripped{"g", "", "1"}, handle{"h", "", "rad"}, opening{"o", "", "rad"};
  World() {
    clock.add(door, 1ms);
    core::connectPorts(arm, door.port("armTarget"));
    core::connectPorts(grip, door.port("gripCommand"));
    core::connectPorts(torque, door.port("handleTorque"));
    core::connectPorts(pull, door.port("pullForce"));
    core::connectPorts(door.port("armPosition"), arm_position);
    core::connectPorts(door.port("gripped"), gripped);
    core::connectPorts(door.port("handleAngle"), handle);
    core::connectPorts(door.port("doorAngle"), opening);
    EXPECT_TRUE(door.configure());
    EXPECT_TRUE(door.start());
  }
  /// Runs `seconds` with the given commands refreshed every ms (as a Constant would).
  void run(double seconds, double grip_cmd, double torque_cmd, double pull_cmd) {
    for (int i = 0; i < static_cast<int>(seconds * 1000); ++i) {
      grip.write(grip_cmd);
      torque.write(torque_cmd);
      pull.write(pull_cmd);
      clock.advance(1ms);
    }
  }
  double value(core::InputPort<double>& port) {
    double v = -1.0;
    (void)port.read(v);
    return v;
  }
};

TEST(DoorSim, TheDoorOpensOnlyAfterGraspTurnPastTheLatchAndPull) {
  World w;
  w.run(0.5, 1.0, 0.0, 5.0);  // gripping and pulling far from the handle does nothing
  EXPECT_EQ(w.value(w.gripped), 0.0);
  w.arm.write(0.5);
  w.run(1.0, 0.0, 0.0, 0.0);  // the arm reaches the handle (τ = 0.1 s)
  EXPECT_NEAR(w.value(w.arm_position), 0.5, 1e-3);
  w.run(0.1, 1.0, 0.0, 0.0);
  EXPECT_EQ(w.value(w.gripped), 1.0);
  w.run(2.0, 1.0, 0.0, 8.0);  // pulling a latched door: it stays closed
  EXPECT_EQ(w.value(w.opening), 0.0);
  w.run(2.0, 1.0, 1.2, 0.0);  // 1.2 N·m against 2 N·m/rad settles at 0.6 rad: still latched
  EXPECT_NEAR(w.value(w.handle), 0.6, 0.01);
  w.run(2.0, 1.0, 1.2, 8.0);
  EXPECT_EQ(w.value(w.opening), 0.0);
  w.run(2.0, 1.0, 2.0, 0.0);  // 1 rad: past the latch
  EXPECT_GT(w.value(w.handle), 0.7);
  w.run(3.0, 1.0, 0.0, 6.0);
  EXPECT_GT(w.value(w.opening), 1.2);
}

TEST(DoorSim, CommandsThatStopComingCountAsZero) {
  World w;
  w.arm.write(0.5);
  w.run(1.0, 1.0, 0.0, 0.0);
  ASSERT_EQ(w.value(w.gripped), 1.0);
  w.clock.advance(100ms);  // nobody sends the grip command: the watchdog (50 ms) opens the gripper
  EXPECT_EQ(w.value(w.gripped), 0.0);
}

// A broken set-point source writes NaN, then inf: the door refuses the sample, turns the handle on
// with the last finite torque (timed out after 50 ms like any silent command), says so once per
// episode, and applies the next finite torque again; nothing non-finite reaches its state.
TEST(DoorSim, ANonFiniteCommandIsRefusedTheLastFiniteOneHoldsAndTheEventIsEmittedOnce) {
  World w;
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(w.door.port("events"), events, core::ConnPolicy::buffer(16));
  core::InputPort<double> applied{"applied", "", "N·m"};
  core::connectPorts(w.door.port("appliedHandleTorque"), applied);
  w.arm.write(0.5);
  w.run(1.0, 1.0, 0.0, 0.0);
  w.run(1.0, 1.0, 1.2, 0.0);  // grasped, turning: 0.6 rad at rest
  ASSERT_EQ(w.value(w.gripped), 1.0);
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    const double turned = w.value(w.handle);
    long allocations = 0;
    for (int i = 0; i < 30; ++i) {  // within command_timeout: the last finite torque holds
      allocations += test_support::allocationsDuring([&] { w.run(0.001, 1.0, bad, 0.0); });
      ASSERT_EQ(w.value(applied), 1.2) << i;
      ASSERT_TRUE(std::isfinite(w.value(w.handle))) << i;
    }
    EXPECT_EQ(allocations, 0);
    EXPECT_NEAR(w.value(w.handle), turned, 0.01);  // held, not driven by the refused value
    w.run(0.1, 1.0, bad, 0.0);                      // past command_timeout: the stale torque counts as 0
    EXPECT_EQ(w.value(applied), 0.0);
    EXPECT_LT(w.value(w.handle), turned);           // the spring turns the handle back
    core::Event e;
    ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
    EXPECT_EQ(e.name.str(), "e_command_not_finite");
    EXPECT_NE(events.read(e), core::FlowStatus::NewData) << e.name.str();  // once per episode
    EXPECT_EQ(w.door.state(), core::State::Running);
    w.run(1.0, 1.0, 1.2, 0.0);  // a finite torque again: applied, the episode over
    EXPECT_EQ(w.value(applied), 1.2);
    EXPECT_NEAR(w.value(w.handle), 0.6, 0.01);
  }
}

TEST(DoorSim, ItsStepsAllocateNothing) {
  World w;
  w.arm.write(0.5);
  w.run(0.1, 1.0, 0.0, 0.0);  // every connection has carried a sample
  const long allocations = test_support::allocationsDuring([&] { w.run(2.0, 1.0, 2.0, 6.0); });
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace cobra::components
