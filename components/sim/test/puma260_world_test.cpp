// Puma260World on the lockstep clock with the unchanged drivers: Puma260EtherCATMaster drives the
// MuJoCo arm through its `bus` property (ready, nest, operative, a press on the surface), the
// FTSens chain (SimulatedFTSens -> CAN -> FTSensDriver) reads the world's sensor wrench, faults
// (drive over-current, working counter) end in the master's Fault with their events, updates
// allocate nothing, and bad properties are refused with the file named.

#include "cobra/components/sim/puma260_world.hpp"

#include <gtest/gtest.h>

#include "cobra/components/drivers/ftsens_driver.hpp"
#include "cobra/components/drivers/puma260_ethercat_master.hpp"
#include "cobra/components/sim/simulated_ftsens.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/kinematics/puma260.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

const std::string kModel = std::string(COBRA_SOURCE_DIR) + "/apps/puma260/world/puma260.xml";
const std::vector<double> kReady = {0.0, 1.5707963267948966, -1.5707963267948966, 0.0, 0.0, 0.0};  // the master's default

struct Rig {
  Puma260World world{"World"};
  Puma260EtherCATMaster master{"Puma"};
  SimulatedFTSens ftsens_sim{"FTSensSim"};
  FTSensDriver ftsens{"FTSens"};
  core::LockstepClock clock;
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<KDL::JntArray> true_position{"q", "", "rad"};
  core::InputPort<KDL::Wrench> sensor_wrench{"w", "", "N, N·m"}, measured_wrench{"mw", "", "N, N·m"};
  core::InputPort<KDL::Frame> tool_pose{"tool", "", "m"};
  core::InputPort<double> contact_force{"f", "", "N"}, penetration{"p", "", "m"};
  core::OutputPort<KDL::JntArray> des_position{"dq", "", "rad", KDL::JntArray(6)};

  Rig() {
    world.setProperty("model", kModel);
    master.setProperty("bus", "sim:World");
    master.setProperty("move_speed", 1.0);
    ftsens.setProperty("bus", "sim:FTSensSim");
    for (core::Component* c : std::initializer_list<core::Component*>{&world, &master, &ftsens_sim, &ftsens})
      clock.add(*c, 1ms);
    core::connectPorts(world.port("sensorWrench"), ftsens_sim.port("trueWrench"));
    core::connectPorts(master.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(world.port("truePosition"), true_position);
    core::connectPorts(world.port("sensorWrench"), sensor_wrench);
    core::connectPorts(ftsens.port("measWrench"), measured_wrench);
    core::connectPorts(world.port("toolPose"), tool_pose);
    core::connectPorts(world.port("contactForce"), contact_force);
    core::connectPorts(world.port("penetration"), penetration);
    core::connectPorts(des_position, master.port("desJointPosition"));
    for (core::Component* c : std::initializer_list<core::Component*>{&world, &master, &ftsens_sim, &ftsens}) {
      EXPECT_TRUE(c->configure()) << c->name() << ": " << c->lastError();
      EXPECT_TRUE(c->start()) << c->name();
    }
  }
  std::vector<std::string> runUntil(const std::string& event, std::chrono::milliseconds limit) {
    std::vector<std::string> seen;
    for (auto t = 0ms; t < limit; t += 1ms) {
      clock.advance(1ms);
      core::Event e;
      bool found = false;
      while (events.read(e) == core::FlowStatus::NewData) {
        seen.push_back(e.name.str());
        found = found || seen.back() == event;
      }
      if (found) break;
    }
    return seen;
  }
  template <class T>
  T last(core::InputPort<T>& port) {
    T value{};
    EXPECT_NE(port.read(value), core::FlowStatus::NoData);
    return value;
  }
  void operative() {
    EXPECT_EQ(runUntil("e_initialized", 50ms), (std::vector<std::string>{"e_initialized"}));
    master.call("askReady");
    EXPECT_EQ(runUntil("e_ready_reached", 8000ms), (std::vector<std::string>{"e_ready_reached"}));
    master.call("askOperative");
    EXPECT_EQ(runUntil("e_operative", 10ms), (std::vector<std::string>{"e_operative"}));
  }
};

TEST(Puma260World, TheMasterDrivesTheMujocoArmFromTheNestToReadyAndBack) {
  Rig rig;
  EXPECT_EQ(rig.runUntil("e_initialized", 50ms), (std::vector<std::string>{"e_initialized"}));
  rig.master.call("askReady");
  EXPECT_EQ(rig.runUntil("e_ready_reached", 8000ms), (std::vector<std::string>{"e_ready_reached"}));
  KDL::JntArray q = rig.last(rig.true_position);
  for (unsigned i = 0; i < 6; ++i) EXPECT_NEAR(q(i), kReady[i], 2e-3) << "joint " << i + 1;
  // Arm straight up, tool up: the sensor carries the tool's weight, pressed along its -z.
  const KDL::Wrench w = rig.last(rig.sensor_wrench);
  EXPECT_NEAR(w.force.z(), -0.05 * 9.81, 0.02);
  EXPECT_NEAR(rig.last(rig.tool_pose).p.z(), 0.3302 + 0.2032 + 0.2032 + 0.05537 + 0.118, 2e-3);
  // The same wrench through the FTSens on CAN and its driver (0.25 N resolution, noise).
  EXPECT_NEAR(rig.last(rig.measured_wrench).force.z(), w.force.z(), 0.5);
  rig.master.call("askNest");
  EXPECT_EQ(rig.runUntil("e_nest_reached", 8000ms), (std::vector<std::string>{"e_nest_reached"}));
  q = rig.last(rig.true_position);
  const std::vector<double> nest = rig.world.getProperty<std::vector<double>>("initial_position");
  for (unsigned i = 0; i < 6; ++i) EXPECT_NEAR(q(i), nest[i], 2e-3) << "joint " << i + 1;
  EXPECT_EQ(rig.last(rig.contact_force), 0.0);
}

TEST(Puma260World, TheSurfaceCylinderIsAReadOnlyPropertyOfTheFilesGeometry) {
  Rig rig;
  // apps/puma260/world/puma260.xml: radius 0.08 m, half-length 0.05 m, centred at (0.35, 0, 0.035) m,
  // its axis turned onto the base x axis by Ry(pi/2).
  const std::vector<double> want{0.30, 0.0, 0.035, 0.40, 0.0, 0.035, 0.08};
  const std::vector<double> got = rig.world.getProperty<std::vector<double>>("surface_cylinder");
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-9) << "value " << i;
}

TEST(Puma260World, ToolPressedOnTheSurfaceThroughTheMasterShowsContactForceAndPenetration) {
  Rig rig;
  rig.operative();
  kinematics::Puma260Solver solver({}, kinematics::Puma260Solver::defaultLimits(), KDL::Frame::Identity(),
                                   KDL::Frame(KDL::Vector(0, 0, 0.118)));
  KDL::JntArray seed(6), goal(6);
  seed(1) = 1.2;
  seed(2) = -2.4;
  seed(4) = -0.4;
  // Tool pointing down, 0.2 mm below the top of the surface (z = 0.115 m): about 9 N, which the
  // shoulder drive holds with the arm's weight within its 14.1 N·m peak torque.
  ASSERT_EQ(solver.inverse(KDL::Frame(KDL::Rotation::RotX(M_PI), KDL::Vector(0.35, 0.0, 0.1148)), seed, goal),
            kinematics::IkStatus::Ok);
  // Above the goal first (3 s ramp in joint space), then down onto the surface (1 s).
  KDL::JntArray above(6);
  ASSERT_EQ(solver.inverse(KDL::Frame(KDL::Rotation::RotX(M_PI), KDL::Vector(0.35, 0.0, 0.14)), seed, above),
            kinematics::IkStatus::Ok);
  const auto ramp = [&](const KDL::JntArray& from, const KDL::JntArray& to, int steps) {
    KDL::JntArray cmd(6);
    for (int k = 1; k <= steps; ++k) {
      for (unsigned i = 0; i < 6; ++i) cmd(i) = from(i) + (to(i) - from(i)) * k / steps;
      rig.des_position.write(cmd);
      rig.clock.advance(1ms);
    }
  };
  KDL::JntArray ready(6);
  for (unsigned i = 0; i < 6; ++i) ready(i) = kReady[i];
  ramp(ready, above, 3000);
  EXPECT_EQ(rig.last(rig.contact_force), 0.0);
  ramp(above, goal, 1000);
  EXPECT_EQ(rig.runUntil("never", 1000ms), std::vector<std::string>{});  // no fault
  const double force = rig.last(rig.contact_force);
  EXPECT_GT(force, 3.0);
  EXPECT_GT(rig.last(rig.penetration), 0.0);
  EXPECT_LT(rig.last(rig.penetration), 1e-3);
  // Tool down: the surface pushes the tool, and so the sensor, towards its -z (sensor axes); the
  // tool's weight (0.05 kg) pulls the other way.
  EXPECT_NEAR(rig.last(rig.sensor_wrench).force.z(), -(force - 0.05 * 9.81), 0.05 * force);
  EXPECT_NEAR(rig.last(rig.tool_pose).p.z(), 0.115 - rig.last(rig.penetration), 1e-3);
}

TEST(Puma260World, AWrongWorkingCounterPutsTheMasterInFaultWithABusFaultEvent) {
  Rig rig;
  rig.operative();
  rig.world.call("injectWorkingCounterFault", 2);
  const auto seen = rig.runUntil("e_bus_fault", 5ms);
  EXPECT_EQ(seen, (std::vector<std::string>{"e_bus_fault"}));
  EXPECT_EQ(rig.master.call<std::string>("busFault"),
            "working counter 15, expected 18: a slave did not process its datagram (the master quick-stopped every "
            "drive)");
  rig.runUntil("never", 500ms);
  EXPECT_CONTAINS(rig.master.call<std::string>("slaveStatus", 0), "switch_on_disabled");
  // Switched off, the brakes hold the arm where it stopped.
  const KDL::JntArray q = rig.last(rig.true_position);
  rig.runUntil("never", 500ms);
  const KDL::JntArray later = rig.last(rig.true_position);
  for (unsigned i = 0; i < 6; ++i) EXPECT_NEAR(later(i), q(i), 1e-5) << "joint " << i + 1;
  rig.master.call("askFaultReset");
  EXPECT_EQ(rig.runUntil("e_initialized", 50ms), (std::vector<std::string>{"e_fault_reset", "e_initialized"}));
}

TEST(Puma260World, ADriveFaultIsTheMastersDriveFault) {
  Rig rig;
  rig.operative();
  rig.world.call("injectFault", 1);
  EXPECT_EQ(rig.runUntil("e_drive_fault", 10ms), (std::vector<std::string>{"e_drive_fault"}));
  EXPECT_CONTAINS(rig.master.call<std::string>("slaveStatus", 1), "fault");
}

TEST(Puma260World, UpdatesAllocateNothing) {
  Rig rig;
  rig.operative();
  EXPECT_EQ(test_support::allocationsDuring([&] { rig.clock.advance(200ms); }), 0);
}

TEST(Puma260World, BadPropertiesAreRefusedNamingTheFile) {
  core::LockstepClock clock;
  Puma260World world("World");
  clock.add(world, 1ms);
  EXPECT_FALSE(world.configure());
  EXPECT_EQ(world.lastError(),
            "component 'World': property model is empty: give the MJCF file of the world (e.g. apps/puma260/world/puma260.xml)");
  world.setProperty("model", std::string("/nonexistent/puma.xml"));
  EXPECT_FALSE(world.configure());
  EXPECT_CONTAINS(world.lastError(), "property model: /nonexistent/puma.xml: cannot load the MuJoCo model: ");
  world.setProperty("model", kModel);
  world.setProperty("initial_position", std::vector<double>{0, 0, 0});
  EXPECT_FALSE(world.configure());
  EXPECT_EQ(world.lastError(), "component 'World': property initial_position has 3 numbers; give 6 joint angles in rad");
  EXPECT_THROW(world.call("injectFault", 0), std::exception);
  world.setProperty("initial_position", kReady);
  world.setProperty("encoder_noise", -1.0);
  EXPECT_FALSE(world.configure());
  EXPECT_EQ(world.lastError(), "component 'World': property encoder_noise = -1.000000 rad; expected >= 0 (a standard deviation)");
  world.setProperty("encoder_noise", 1e-5);
  EXPECT_TRUE(world.configure());
  EXPECT_EQ(world.call<std::string>("surface"),
            "cylinder centre (0.3500, 0.0000, 0.0350) m, axis (1.0000, 0.0000, 0.0000), radius 0.0800 m, length 0.1000 m");
}

}  // namespace
}  // namespace cobra::components

