// The door example's simulated world: what the task chart relies on happens, and only then.
#include "cobra/components/door/door_sim.hpp"

#include <gtest/gtest.h>

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

TEST(DoorSim, ItsStepsAllocateNothing) {
  World w;
  w.arm.write(0.5);
  w.run(0.1, 1.0, 0.0, 0.0);  // every connection has carried a sample
  const long allocations = test_support::allocationsDuring([&] { w.run(2.0, 1.0, 2.0, 6.0); });
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace cobra::components
