// Puma260Master (thesis §6.2.1, Fig. 6.4) on cobra::sim's simulated bus (stepped here before each
// master cycle, as a sim-world component would): the state sequence through ready,
// nest and operative, refused requests, a drive fault and its reset, a working-counter mismatch,
// and position / velocity / torque commands reaching the joints.

#include "cobra/fieldbus/puma260_master.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/kinematics/puma260.hpp"
#include "cobra/sim/puma260_ethercat_bus.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using namespace cobra::fieldbus;
namespace ev = master_event;
constexpr double kCycle = 1e-3;  // s

Puma260MasterConfig config(ControlMode mode = ControlMode::Position) {
  Puma260MasterConfig c;
  c.control_mode = mode;
  const auto limits = cobra::kinematics::Puma260Solver::defaultLimits();
  for (unsigned i = 0; i < 6; ++i) {
    c.lower[i] = limits.lower[i];
    c.upper[i] = limits.upper[i];
  }
  c.nest = {0.0, -0.3, -0.3, 0.0, 0.2, 0.0};
  c.ready = {0.3, 0.5, -1.0, 0.2, -0.4, 0.5};
  c.move_speed = 1.0;
  return c;
}

struct Rig {
  cobra::sim::Puma260EtherCatBus bus;
  Puma260Master master;
  JointCommands commands;
  std::uint32_t seen = 0;
  explicit Rig(const Puma260MasterConfig& c = config()) : master(c, bus) {}
  /// One cycle: the world takes the outputs of the previous cycle and steps, then the master.
  std::uint32_t cycle() {
    bus.step(kCycle);
    return master.step(kCycle, commands);
  }
  /// Runs until `event` or `seconds`; returns whether it came.
  bool runUntil(std::uint32_t event, double seconds) {
    for (int i = 0; i < static_cast<int>(seconds / kCycle); ++i) {
      const std::uint32_t e = cycle();
      seen |= e;
      if (e & event) return true;
    }
    return false;
  }
  void run(double seconds) { runUntil(0, seconds); }
  double error(const JointVector& q) const {
    double worst = 0.0;
    for (int i = 0; i < 6; ++i)
      worst =
          std::max(worst, std::abs(master.position()[static_cast<std::size_t>(i)] - q[static_cast<std::size_t>(i)]));
    return worst;
  }
};

TEST(Puma260Master, GoesThroughTheStatesOfFigure64) {
  Rig rig;
  EXPECT_EQ(rig.master.state(), MasterState::NotInitialized);
  ASSERT_TRUE(rig.runUntil(ev::kInitialized, 0.05));
  EXPECT_EQ(rig.master.state(), MasterState::Initialized);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(rig.bus.arm().drive(i).state(), cobra::sim::Cia402State::OperationEnabled);

  ASSERT_TRUE(rig.master.request(Request::Ready));
  EXPECT_EQ(rig.master.state(), MasterState::MovingToReady);
  rig.run(0.1);
  EXPECT_EQ(rig.master.state(), MasterState::MovingToReady);  // 1 rad at 1 rad/s peak takes ~1.9 s
  ASSERT_TRUE(rig.runUntil(ev::kReadyReached, 5.0));
  EXPECT_EQ(rig.master.state(), MasterState::ReadyPosition);
  EXPECT_LT(rig.error(config().ready), 2e-3);

  ASSERT_TRUE(rig.master.request(Request::Nest));
  EXPECT_EQ(rig.master.state(), MasterState::MovingToNest);
  ASSERT_TRUE(rig.runUntil(ev::kNestReached, 5.0));
  EXPECT_EQ(rig.master.state(), MasterState::NestPosition);
  EXPECT_LT(rig.error(config().nest), 2e-3);

  ASSERT_TRUE(rig.master.request(Request::Ready));
  ASSERT_TRUE(rig.runUntil(ev::kReadyReached, 5.0));
  ASSERT_TRUE(rig.master.request(Request::Operative));
  ASSERT_TRUE(rig.runUntil(ev::kOperative, 0.01));
  EXPECT_EQ(rig.master.state(), MasterState::Operative);
  EXPECT_EQ(rig.seen & ev::kDriveFault, 0U);
}

TEST(Puma260Master, RefusesRequestsTheCurrentStateDoesNotAllow) {
  Rig rig;
  EXPECT_FALSE(rig.master.request(Request::Ready));  // not initialised yet
  ASSERT_TRUE(rig.runUntil(ev::kInitialized, 0.05));
  EXPECT_FALSE(rig.master.request(Request::Nest));        // nest only from ready
  EXPECT_FALSE(rig.master.request(Request::Operative));   // operative only from ready
  EXPECT_FALSE(rig.master.request(Request::FaultReset));  // no fault
  EXPECT_EQ(rig.master.state(), MasterState::Initialized);
  ASSERT_TRUE(rig.master.request(Request::Ready));
  EXPECT_FALSE(rig.master.request(Request::Nest));  // still moving
  EXPECT_FALSE(rig.master.request(Request::Ready));
  ASSERT_TRUE(rig.runUntil(ev::kReadyReached, 5.0));
  ASSERT_TRUE(rig.master.request(Request::Nest));
  ASSERT_TRUE(rig.runUntil(ev::kNestReached, 5.0));
  EXPECT_FALSE(rig.master.request(Request::Operative));  // not from nest
  EXPECT_FALSE(rig.master.request(Request::Nest));
  EXPECT_EQ(rig.master.state(), MasterState::NestPosition);
}

TEST(Puma260Master, ADriveFaultStopsCommandingAndAResetReinitialises) {
  Rig rig;
  ASSERT_TRUE(rig.runUntil(ev::kInitialized, 0.05));
  ASSERT_TRUE(rig.master.request(Request::Ready));
  rig.run(0.5);
  rig.bus.arm().drive(2).injectFault(cobra::sim::error_code::kOverCurrent);
  ASSERT_TRUE(rig.runUntil(ev::kDriveFault, 0.01));
  EXPECT_EQ(rig.master.state(), MasterState::Fault);
  EXPECT_EQ(rig.master.faultSlave(), 2);
  EXPECT_EQ(rig.master.faultCode(), cobra::sim::error_code::kOverCurrent);
  rig.run(0.5);
  for (int i = 0; i < 6; ++i) {  // every drive is off: the faulted one in Fault, the others quick-stopped
    const auto s = rig.bus.arm().drive(i).state();
    EXPECT_EQ(s, i == 2 ? cobra::sim::Cia402State::Fault : cobra::sim::Cia402State::SwitchOnDisabled) << "joint " << i;
  }
  const JointVector stopped = rig.master.position();
  rig.run(0.5);
  EXPECT_LT(rig.error(stopped), 1e-4);  // brakes hold, nothing commands a motion
  EXPECT_FALSE(rig.master.request(Request::Ready));
  ASSERT_TRUE(rig.master.request(Request::FaultReset));
  ASSERT_TRUE(rig.runUntil(ev::kFaultReset, 0.01));
  ASSERT_TRUE(rig.runUntil(ev::kInitialized, 0.05));
  EXPECT_EQ(rig.master.faultSlave(), -1);
  ASSERT_TRUE(rig.master.request(Request::Ready));
  ASSERT_TRUE(rig.runUntil(ev::kReadyReached, 5.0));
}

Rig& operative(Rig& rig) {
  EXPECT_TRUE(rig.runUntil(ev::kInitialized, 0.05));
  EXPECT_TRUE(rig.master.request(Request::Ready));
  EXPECT_TRUE(rig.runUntil(ev::kReadyReached, 5.0));
  EXPECT_TRUE(rig.master.request(Request::Operative));
  EXPECT_TRUE(rig.runUntil(ev::kOperative, 0.01));
  return rig;
}

TEST(Puma260Master, PositionModeTracksCommandsInsideTheLimits) {
  Rig rig;
  operative(rig);
  rig.run(0.2);
  EXPECT_LT(rig.error(config().ready), 2e-3);  // no command yet: holds
  rig.commands.position_valid = true;
  rig.commands.position = config().ready;
  for (int k = 0; k < 2000; ++k) {  // a 0.25 rad/s ramp on joint 1 and a sine on joint 3
    const double t = k * kCycle;
    rig.commands.position[0] = config().ready[0] + 0.25 * t;
    rig.commands.position[2] = config().ready[2] + 0.1 * std::sin(3.0 * t);
    rig.cycle();
    if (k > 200) {
      EXPECT_LT(rig.error(rig.commands.position), 0.02) << "t = " << t;
    }
  }
  bool clamped = false;
  for (int k = 0; k < 4000; ++k) {  // joint 4 ramps at 1 rad/s from 0.2 rad past its 2.97 rad limit
    rig.commands.position[3] = config().ready[3] + 1e-3 * k;
    if (rig.cycle() & ev::kCommandClamped) clamped = true;
  }
  EXPECT_TRUE(clamped);
  EXPECT_EQ(rig.master.state(), MasterState::Operative);
  EXPECT_NEAR(rig.master.position()[3], config().upper[3], 2e-3);
}

TEST(Puma260Master, VelocityModeTracksCommands) {
  Rig rig(config(ControlMode::Velocity));
  operative(rig);
  rig.commands.velocity_valid = true;
  rig.commands.velocity = {0.2, -0.1, 0.0, 0.3, 0.0, -0.5};
  const JointVector start = rig.master.position();
  rig.run(1.0);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(rig.master.velocity()[i], rig.commands.velocity[i], 0.01) << "joint " << i;
    EXPECT_NEAR(rig.master.position()[i] - start[i], rig.commands.velocity[i], 0.03) << "joint " << i;
  }
}

TEST(Puma260Master, TorqueModeAppliesTheCommandedTorque) {
  Rig rig(config(ControlMode::Torque));
  operative(rig);
  // Gravity compensation from the arm model plus 0.05 N·m on the wrist joints.
  rig.commands.torque_valid = true;
  const cobra::sim::Puma260Arm model(cobra::sim::Puma260ArmModel::defaults());  // the bus's default arm
  for (int k = 0; k < 300; ++k) {
    rig.commands.torque = model.gravityTorque(rig.master.position());
    for (std::size_t i = 3; i < 6; ++i) rig.commands.torque[i] = 0.05;
    rig.cycle();
  }
  rig.cycle();  // the drives take a command one cycle after the master sent it
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_NEAR(rig.master.torque()[i], rig.commands.torque[i], 1e-9) << "joint " << i;
  EXPECT_GT(rig.master.velocity()[3], 0.5);                        // 0.05 N·m on 0.005 kg·m² for 0.3 s
  EXPECT_NEAR(rig.master.position()[1], config().ready[1], 0.01);  // compensated: the shoulder stays
}

TEST(Puma260Master, AWrongWorkingCounterIsABusFaultThatQuickStopsEveryDrive) {
  Rig rig;
  operative(rig);
  rig.commands.position_valid = true;
  rig.commands.position = config().ready;
  for (int k = 0; k < 100; ++k) {  // joint 1 moving at 0.5 rad/s
    rig.commands.position[0] += 0.5 * kCycle;
    rig.cycle();
  }
  ASSERT_GT(std::abs(rig.bus.arm().drive(0).velocity()), 0.1);
  rig.bus.injectWorkingCounterFault(3);
  rig.seen = 0;
  const std::uint32_t first = rig.cycle();
  EXPECT_TRUE(first & ev::kWorkingCounterMismatch);
  EXPECT_EQ(first & ev::kBusError, 0U);  // distinct from a link down
  EXPECT_EQ(first & ev::kDriveFault, 0U);
  EXPECT_EQ(rig.master.state(), MasterState::Fault);
  EXPECT_EQ(rig.master.workingCounterFault().expected, 18);
  EXPECT_EQ(rig.master.workingCounterFault().received, 15);
  EXPECT_TRUE(rig.cycle() & ev::kWorkingCounterMismatch);  // reported each cycle it lasts
  EXPECT_TRUE(rig.cycle() & ev::kWorkingCounterMismatch);
  EXPECT_EQ(rig.cycle() & ev::kWorkingCounterMismatch, 0U);  // the 3 cycles are over
  rig.run(0.5);
  EXPECT_EQ(rig.master.state(), MasterState::Fault);
  for (int i = 0; i < 6; ++i) {  // quick stop (option 2): stopped, then switched off, brakes on
    EXPECT_EQ(rig.bus.arm().drive(i).state(), cobra::sim::Cia402State::SwitchOnDisabled) << "drive " << i;
    EXPECT_NEAR(rig.bus.arm().drive(i).velocity(), 0.0, 1e-6) << "drive " << i;
  }
  ASSERT_TRUE(rig.master.request(Request::FaultReset));
  EXPECT_TRUE(rig.runUntil(ev::kInitialized, 0.1));
}

TEST(Puma260Master, CyclesAllocateNothing) {
  Rig rig;
  operative(rig);
  rig.commands.position_valid = true;
  rig.commands.position = config().ready;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { rig.run(0.5); }), 0);
}

TEST(Puma260Master, RefusesAnInvalidConfigurationNamingTheParameter) {
  cobra::sim::Puma260EtherCatBus bus;
  Puma260MasterConfig c = config();
  c.ready[2] = 3.2;
  EXPECT_EQ(cobra::test_support::messageOf([&] { Puma260Master m(c, bus); }),
            "Puma 260 master: ready[2] = 3.2 rad is outside the joint limits [-3.92699, 0.785398] rad");
  c = config();
  c.move_speed = 0.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { Puma260Master m(c, bus); }),
                  "move_speed = 0 rad/s, expected > 0");
}

}  // namespace
