// Puma260EtherCATMaster on the lockstep clock, on the simulated drives of a SimulatedPuma260
// component found through its `bus` property: the states of Fig. 6.4 on currentState and the
// events, refused requests, a drive fault and its reset, a working-counter mismatch (e_bus_fault),
// position / velocity / torque commands through the ports, no allocation in updateHook, and the
// messages of bad properties.

#include "cobra/components/drivers/puma260_ethercat_master.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cobra/components/sim/simulated_puma260.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Bench {
  SimulatedPuma260 arm{"PumaSim"};
  Puma260EtherCATMaster master{"Puma"};
  core::LockstepClock clock;
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<core::TaskState> state{"state", "", ""};
  core::InputPort<KDL::JntArray> position{"q", "", "rad"}, velocity{"qd", "", "rad/s"}, torque{"tau", "", "N·m"};
  core::OutputPort<KDL::JntArray> des_position{"dq", "", "rad", KDL::JntArray(6)};
  core::OutputPort<KDL::JntArray> des_velocity{"dqd", "", "rad/s", KDL::JntArray(6)};
  core::OutputPort<KDL::JntArray> des_torque{"dtau", "", "N·m", KDL::JntArray(6)};
  std::vector<std::string> states;

  explicit Bench(const std::string& mode = "position") {
    master.setProperty("control_mode", mode);
    master.setProperty("move_speed", 1.0);
    master.setProperty("bus", "sim:PumaSim");
    clock.add(arm, 1ms);
    clock.add(master, 1ms);
    core::connectPorts(master.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(master.port("currentState"), state, core::ConnPolicy::buffer(64));
    core::connectPorts(master.port("measJointPosition"), position);
    core::connectPorts(master.port("measJointVelocity"), velocity);
    core::connectPorts(master.port("measJointTorque"), torque);
    core::connectPorts(des_position, master.port("desJointPosition"));
    core::connectPorts(des_velocity, master.port("desJointVelocity"));
    core::connectPorts(des_torque, master.port("desJointTorque"));
    EXPECT_TRUE(arm.configure());
    EXPECT_TRUE(master.configure());
    EXPECT_TRUE(arm.start());
    EXPECT_TRUE(master.start());
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    core::TaskState s;
    while (state.read(s) == core::FlowStatus::NewData) states.push_back(s.path.str());
    return names;
  }
  /// Advances until `event` is emitted (at most `limit`); returns the events seen on the way.
  std::vector<std::string> runUntil(const std::string& event, std::chrono::milliseconds limit) {
    std::vector<std::string> all;
    for (auto t = 0ms; t < limit; t += 1ms) {
      clock.advance(1ms);
      for (auto& e : takeEvents()) all.push_back(e);
      if (!all.empty() && all.back() == event) break;
    }
    return all;
  }
  KDL::JntArray read(core::InputPort<KDL::JntArray>& port) {
    KDL::JntArray q;
    EXPECT_NE(port.read(q), core::FlowStatus::NoData);
    return q;
  }
  void operative() {
    EXPECT_EQ(runUntil("e_initialized", 50ms), (std::vector<std::string>{"e_initialized"}));
    master.call("askReady");
    EXPECT_EQ(runUntil("e_ready_reached", 5000ms), (std::vector<std::string>{"e_ready_reached"}));
    master.call("askOperative");
    EXPECT_EQ(runUntil("e_operative", 10ms), (std::vector<std::string>{"e_operative"}));
  }
};

TEST(Puma260EtherCATMaster, StatesAndEventsFollowFigure64) {
  Bench b;
  EXPECT_EQ(b.runUntil("e_initialized", 50ms), (std::vector<std::string>{"e_initialized"}));
  b.master.call("askReady");
  EXPECT_EQ(b.runUntil("e_ready_reached", 5000ms), (std::vector<std::string>{"e_ready_reached"}));
  const KDL::JntArray ready = b.read(b.position);
  EXPECT_NEAR(ready(1), 1.5707963, 2e-3);
  EXPECT_NEAR(ready(2), -1.5707963, 2e-3);
  b.master.call("askNest");
  EXPECT_EQ(b.runUntil("e_nest_reached", 5000ms), (std::vector<std::string>{"e_nest_reached"}));
  EXPECT_NEAR(b.read(b.position)(2), -3.1415927, 2e-3);
  b.master.call("askReady");
  EXPECT_EQ(b.runUntil("e_ready_reached", 5000ms), (std::vector<std::string>{"e_ready_reached"}));
  b.master.call("askOperative");
  EXPECT_EQ(b.runUntil("e_operative", 10ms), (std::vector<std::string>{"e_operative"}));
  EXPECT_EQ(b.states,
            (std::vector<std::string>{"NotInitialized", "Initialized", "MovingToReady", "ReadyPosition", "MovingToNest",
                                      "NestPosition", "MovingToReady", "ReadyPosition", "Operative"}));
}

TEST(Puma260EtherCATMaster, RequestsTheStateDoesNotAllowAreRefusedWithAnEvent) {
  Bench b;
  b.runUntil("e_initialized", 50ms);
  b.master.call("askNest");
  b.master.call("askOperative");
  b.master.call("askFaultReset");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_request_refused", "e_request_refused", "e_request_refused"}));
  b.master.call("askReady");
  b.master.call("askNest");  // still moving
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_request_refused"}));
  EXPECT_EQ(b.states.back(), "MovingToReady");
}

TEST(Puma260EtherCATMaster, ADriveFaultStopsTheRobotUntilReset) {
  Bench b;
  core::InputPort<KDL::JntArray> held{"held", "", "rad"};
  core::connectPorts(b.master.port("heldJointPosition"), held);
  b.operative();
  KDL::JntArray q;
  EXPECT_EQ(held.read(q), core::FlowStatus::NoData);  // not held while operative
  b.arm.call("injectFault", 4);
  EXPECT_EQ(b.runUntil("e_drive_fault", 10ms), (std::vector<std::string>{"e_drive_fault"}));
  EXPECT_EQ(b.states.back(), "Fault");
  // Held: in each cycle in Fault once the joints have been at rest for 0.1 s, the measured joints,
  // for the command chain to re-sync to.
  b.clock.advance(50ms);
  EXPECT_EQ(held.read(q), core::FlowStatus::NoData);
  b.clock.advance(60ms);
  ASSERT_EQ(held.read(q), core::FlowStatus::NewData);
  EXPECT_EQ(q.data, b.read(b.position).data);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { b.clock.advance(5ms); }), 0);
  ASSERT_EQ(held.read(q), core::FlowStatus::NewData);
  EXPECT_EQ(q.data, b.read(b.position).data);
  EXPECT_CONTAINS(b.master.call<std::string>("slaveStatus", 4),
                  "slave 4: simulated Elmo Gold Solo Whistle (CiA 402), fault");
  EXPECT_CONTAINS(b.master.call<std::string>("slaveStatus", 4), "master sees fault");
  b.master.call("askOperative");
  b.master.call("askReady");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_request_refused", "e_request_refused"}));
  b.master.call("askFaultReset");
  EXPECT_EQ(b.runUntil("e_initialized", 50ms), (std::vector<std::string>{"e_fault_reset", "e_initialized"}));
  (void)held.read(q);
  b.master.call("askReady");
  EXPECT_EQ(b.runUntil("e_ready_reached", 5000ms), (std::vector<std::string>{"e_ready_reached"}));
  EXPECT_EQ(held.read(q), core::FlowStatus::OldData);  // out of Fault: not held
}

TEST(Puma260EtherCATMaster, AWrongWorkingCounterIsABusFaultWithTheCountersInBusFault) {
  Bench b;
  b.operative();
  EXPECT_EQ(b.master.call<std::string>("busFault"), "no working-counter mismatch");
  b.arm.call("injectWorkingCounterFault", 3);
  EXPECT_EQ(b.runUntil("never", 5ms), (std::vector<std::string>{"e_bus_fault", "e_bus_fault", "e_bus_fault"}));
  EXPECT_EQ(b.states.back(), "Fault");
  EXPECT_EQ(b.master.call<std::string>("busFault"),
            "working counter 15, expected 18: a slave did not process its datagram (the master quick-stopped every "
            "drive)");
  b.master.call("askFaultReset");
  EXPECT_EQ(b.runUntil("e_initialized", 500ms), (std::vector<std::string>{"e_fault_reset", "e_initialized"}));
}

TEST(Puma260EtherCATMaster, PositionCommandsAreTrackedWithoutAllocating) {
  Bench b;
  b.operative();
  KDL::JntArray q = b.read(b.position);
  const KDL::JntArray start = q;
  const auto follow = [&](int cycles) {
    for (int k = 0; k < cycles; ++k) {
      q(0) += 2e-4;  // 0.2 rad/s
      b.des_position.write(q);
      b.clock.advance(1ms);
    }
  };
  follow(500);
  EXPECT_NEAR(b.read(b.position)(0), q(0), 0.01);
  EXPECT_NEAR(b.read(b.position)(0), start(0) + 0.1, 0.01);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { follow(200); }), 0);
}

// A broken command chain writes NaN, then inf joints: the master refuses them (the drives keep the
// last finite set-point: the arm holds), tells e_command_not_finite once per episode, allocates
// nothing, and follows the next finite command again.
TEST(Puma260EtherCATMaster, ANonFiniteCommandNeverReachesTheDrivesTheArmHoldsAndTheEventIsToldOnce) {
  Bench b;
  b.operative();
  KDL::JntArray q = b.read(b.position);
  for (int k = 0; k < 300; ++k) {  // moving joint 0 at 0.2 rad/s
    q(0) += 2e-4;
    b.des_position.write(q);
    b.clock.advance(1ms);
  }
  b.takeEvents();
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    KDL::JntArray broken = q;
    broken(0) = bad;
    long allocations = 0;
    for (int k = 0; k < 500; ++k)
      allocations += cobra::test_support::allocationsDuring([&] {
        b.des_position.write(broken);
        b.clock.advance(1ms);
      });
    EXPECT_EQ(allocations, 0);
    const KDL::JntArray held = b.read(b.position);
    EXPECT_NEAR(held(0), q(0), 2e-3);  // at the last finite command, not beyond it
    for (unsigned i = 0; i < 6; ++i) EXPECT_TRUE(std::isfinite(held(i))) << i;
    EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_command_not_finite"}));  // once
    EXPECT_EQ(b.states.back(), "Operative");
    for (int k = 0; k < 200; ++k) {  // finite commands again, moving on from the held set-point: followed
      if (k < 50) q(0) += 2e-4;
      b.des_position.write(q);
      b.clock.advance(1ms);
    }
    EXPECT_NEAR(b.read(b.position)(0), q(0), 2e-3);
    EXPECT_TRUE(b.takeEvents().empty());
  }
}

TEST(Puma260EtherCATMaster, VelocityAndTorqueModesActOnTheirPorts) {
  {
    Bench b("velocity");
    b.operative();
    KDL::JntArray v(6);
    v(0) = 0.3;
    v(5) = -0.2;
    for (int k = 0; k < 500; ++k) {
      b.des_velocity.write(v);
      b.clock.advance(1ms);
    }
    EXPECT_NEAR(b.read(b.velocity)(0), 0.3, 0.01);
    EXPECT_NEAR(b.read(b.velocity)(5), -0.2, 0.01);
    EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
                for (int k = 0; k < 100; ++k) {
                  b.des_velocity.write(v);
                  b.clock.advance(1ms);
                }
              }),
              0);
  }
  {
    Bench b("torque");
    b.operative();
    KDL::JntArray tau(6);
    tau(3) = 0.04;  // wrist joint: no gravity in the model
    for (int k = 0; k < 100; ++k) {
      b.des_torque.write(tau);
      b.clock.advance(1ms);
    }
    EXPECT_NEAR(b.read(b.torque)(3), 0.04, 1e-9);
    EXPECT_GT(b.read(b.velocity)(3), 0.5);  // 0.04 N·m on 0.005 kg·m² for 0.1 s
  }
}

TEST(Puma260EtherCATMaster, TheSimulatedArmReportsItsJointsAndRefusesBadInput) {
  Bench b;
  core::InputPort<KDL::JntArray> truth{"truth", "", "rad"};
  core::connectPorts(b.arm.port("trueJointPosition"), truth);
  b.runUntil("e_initialized", 50ms);
  KDL::JntArray q;
  ASSERT_EQ(truth.read(q), core::FlowStatus::NewData);
  EXPECT_NEAR(q(2), -3.1415927, 1e-3);  // powered on in the nominal pose qn (less the sag while enabling)
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { b.arm.call("injectFault", 6); }), "slave 6 is not 0-5");
  SimulatedPuma260 other("PumaSim2");
  core::LockstepClock clock;
  clock.add(other, 1ms);
  other.setProperty("initial_position", std::vector<double>{0, 0});
  EXPECT_CONTAINS(other.configure().message,
                  "component 'PumaSim2': property initial_position has 2 numbers; give 6 joint angles in rad");
}

TEST(Puma260EtherCATMaster, BadPropertiesAreRefusedWithTheirName) {
  SimulatedPuma260 arm("PumaSim");
  Puma260EtherCATMaster m("Puma");
  EXPECT_CONTAINS(m.configure().message, "needs a periodic activity: its period is the EtherCAT cycle");
  core::LockstepClock clock;
  clock.add(arm, 1ms);
  clock.add(m, 1ms);
  ASSERT_TRUE(arm.configure());
  m.setProperty("control_mode", "speed");
  EXPECT_CONTAINS(m.configure().message,
                  "component 'Puma': property control_mode is 'speed'; expected position, velocity or torque");
  m.setProperty("control_mode", "torque");
  m.setProperty("nest_position", std::vector<double>{0, 0, 0, 0, 0});
  EXPECT_CONTAINS(m.configure().message, "property nest_position has 5 numbers; give 6 joint values in rad");
  m.setProperty("nest_position", std::vector<double>{0, 0, 0, 0, 0, 0});
  m.setProperty("bus", "soem:eth0");
  EXPECT_CONTAINS(m.configure().message,
                  "property bus = 'soem:eth0': no CiA 402 (EtherCAT) bus backend 'soem:eth0'; backends that exist: "
                  "'sim:PumaSim' (simulated Puma 260 drives of component 'PumaSim')");
  m.setProperty("bus", "sim:PumaSim");
  m.setProperty("ready_position", std::vector<double>{0, 4.0, 0, 0, 0, 0});
  EXPECT_CONTAINS(m.configure().message,
                  "Puma 260 master: ready[1] = 4 rad is outside the joint limits [-0.785398, 3.92699] rad");
  m.setProperty("ready_position", std::vector<double>{0, 1.0, 0, 0, 0, 0});
  EXPECT_TRUE(m.configure());
}

}  // namespace
}  // namespace cobra::components
