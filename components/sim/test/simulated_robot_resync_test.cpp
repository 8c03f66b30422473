// A simulated robot's command chain, wired as the applications wire it (ARCHITECTURE §7,
// "Continuity in the control path"): a WaypointPath into the CartesianTrajectoryGenerator, its
// set-point through the VariableAdmittance to the robot; the robot's heldCartPose back to the
// admittance's heldPose and the admittance's heldRefPose to the generator's heldPose_1. Mid-motion
// the robot is slowed (speed_scaling) so that it refuses the next command and holds: the admittance
// and the generator re-sync to the held pose in that step, the command stays there while the robot
// holds (no run-away), and the next motion starts from it without a step. For the I-SUR, the UR5
// and the Puma 260's kinematics solver; every step of the re-sync and the hold allocates nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "puncturing_world.hpp"  // jointArray

namespace cobra::components::test {
namespace {

using namespace std::chrono_literals;

/// "{x, y, z, qx, qy, qz, qw}" of `f` moved by (dx, dy, dz) m in the world frame: a waypoint.
std::string waypoint(const KDL::Frame& f, double dx, double dy, double dz) {
  double qx, qy, qz, qw;
  f.M.GetQuaternion(qx, qy, qz, qw);
  char text[256];
  std::snprintf(text, sizeof text, "{ %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g }", f.p.x() + dx, f.p.y() + dy,
                f.p.z() + dz, qx, qy, qz, qw);
  return text;
}

/// The robot end of a chain: its component type and setup (Lua, the component named Robot), and
/// the names of its commanded, measured and held pose ports.
struct RobotSpec {
  std::string type;
  std::string setup;
  std::string command = "desCartPose";
  std::string measured = "measCartPose";
  std::string held = "heldCartPose";
  std::vector<double> measured_joints = {};  // written once on Robot.jointPositions (a solver's start), rad
};

struct Chain {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  core::InputPort<KDL::Frame> measured{"measured", "", "m"};
  core::InputPort<KDL::Frame> held{"held", "", "m"};
  core::InputPort<KDL::Frame> command{"command", "", "m"};
  core::InputPort<core::Event> robot_events{"robotEvents", "", ""};
  core::InputPort<core::Event> admittance_events{"admittanceEvents", "", ""};
  core::InputPort<core::Event> generator_events{"generatorEvents", "", ""};
  KDL::Frame start;  // the tool's pose at configure, where the paths' waypoints are counted from
  core::OutputPort<KDL::JntArray> start_joints{"startJoints", "", "rad"};

  /// The chain for a robot of `type`, at rest at its initial joints; paths 1 and 2 go `first` and
  /// then `second` (Lua tables of dx, dy, dz in m) from where the tool is at configure.
  Chain(const RobotSpec& spec, const std::vector<double>& first, const std::vector<double>& second) {
    addBuiltinPackages(configurator.packages());
    deployer.run("initConfigurator({ 'cobra_sim', 'cobra_control', 'cobra_motion' }, {\n"
                 "  { peer_name = 'Robot', component_type = '" + spec.type + "' },\n"
                 "  { peer_name = 'Path1', component_type = 'WaypointPath' },\n"
                 "  { peer_name = 'Path2', component_type = 'WaypointPath' },\n"
                 "  { peer_name = 'TrajGen', component_type = 'CartesianTrajectoryGenerator' },\n"
                 "  { peer_name = 'Admittance', component_type = 'VariableAdmittance' } })\n"
                 "getReferences()\n"
                 "setActivities({ { peer_name = 'Robot', period = 0.001 }, { peer_name = 'Path1', period = 0.001 },\n"
                 "  { peer_name = 'Path2', period = 0.001 }, { peer_name = 'TrajGen', period = 0.001 },\n"
                 "  { peer_name = 'Admittance', period = 0.001 } })\n" +
                     spec.setup +
                     "\n"
                     "configureComponents({ 'Robot' }) startComponents({ 'Robot' })",
                 "chain.lua");
    core::Component& robot = component("Robot");
    core::connectPorts(robot.port(spec.measured), measured);
    core::connectPorts(robot.port(spec.held), held);
    if (!spec.measured_joints.empty()) {
      core::connectPorts(start_joints, robot.port("jointPositions"));
      start_joints.write(jointArray(spec.measured_joints));
    }
    core::connectPorts(robot.port("events"), robot_events, core::ConnPolicy::buffer(32));
    configurator.clock().advance(1ms);
    EXPECT_EQ(measured.read(start), core::FlowStatus::NewData);
    deployer.run("Path1.waypoints = " + waypoint(start, first[0], first[1], first[2]) + "\n" +
                     "Path2.waypoints = " + waypoint(start, first[0] + second[0], first[1] + second[1],
                                                     first[2] + second[2]) +
                     "\n"
                     "TrajGen.arms_num = 1 TrajGen.max_vel = 0.02 TrajGen.max_ang_vel = 0.2\n"
                     "local all = { 'Path1', 'Path2', 'TrajGen', 'Admittance' }\n"
                     "configureComponents(all)\n"
                     "connectPorts({\n"
                     "  { output = 'Robot." + spec.measured + "', input = 'Path1.measPose' },\n"
                     "  { output = 'Robot." + spec.measured + "', input = 'Path2.measPose' },\n"
                     "  { output = 'Path1.path', input = 'TrajGen.plannedPath', conn_policy = { type = 'buffer', size = 4 } },\n"
                     "  { output = 'Path2.path', input = 'TrajGen.plannedPath', conn_policy = { type = 'buffer', size = 4 } },\n"
                     "  { output = 'TrajGen.desCartPose_1', input = 'Admittance.refPose' },\n"
                     "  { output = 'TrajGen.desCartTwist_1', input = 'Admittance.refTwist' },\n"
                     "  { output = 'Admittance.admPose', input = 'Robot." + spec.command + "' },\n"
                     "  { output = 'Robot." + spec.held + "', input = 'Admittance.heldPose' },\n"
                     "  { output = 'Admittance.heldRefPose', input = 'TrajGen.heldPose_1' } })\n"
                     "startComponents(all)",
                 "chain.lua");
    if (!spec.measured_joints.empty()) {  // a solver publishes its pose on new joints only: again for the paths
      start_joints.write(jointArray(spec.measured_joints));
      configurator.clock().advance(1ms);
    }
    core::connectPorts(component("Admittance").port("admPose"), command);
    core::connectPorts(component("Admittance").port("events"), admittance_events, core::ConnPolicy::buffer(32));
    core::connectPorts(component("TrajGen").port("events"), generator_events, core::ConnPolicy::buffer(32));
    takeEvents(robot_events);
    takeEvents(generator_events);
  }
  core::Component& component(const std::string& name) { return configurator.getReferences().get(name); }
  /// Sends path `path` (Path1 or Path2), has its trajectory generated and started.
  void move(const char* path) {
    component(path).call<void>("askPath");
    configurator.clock().advance(1ms);
    component("TrajGen").call<void>("askGenerateTraj");
    configurator.clock().advance(1ms);
    component("TrajGen").call<void>("askStartMove");
    configurator.clock().advance(1ms);
  }
  static std::vector<std::string> takeEvents(core::InputPort<core::Event>& port) {
    std::vector<std::string> names;
    core::Event e;
    while (port.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  KDL::Frame last(core::InputPort<KDL::Frame>& port) {
    KDL::Frame f;
    EXPECT_NE(port.read(f), core::FlowStatus::NoData);
    return f;
  }
};

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// The refusal mid-motion and the re-sync, for the robot of `type` moving `first` then `second`.
void checkRefusalReSyncsTheChain(const RobotSpec& robot, const std::vector<double>& first,
                                 const std::vector<double>& second) {
  Chain c(robot, first, second);
  c.move("Path1");
  c.configurator.clock().advance(400ms);
  ASSERT_EQ(c.component("TrajGen").call<std::string>("status"), "Moving");
  ASSERT_TRUE(Chain::takeEvents(c.robot_events).empty());
  KDL::Frame before = c.last(c.command);
  // Slowed to 0.2 % of its joint speed: the next command is beyond the bound, the robot holds.
  c.component("Robot").setProperty("speed_scaling", 0.002);
  c.configurator.clock().advance(1ms);  // the robot refuses; the admittance re-syncs in this step
  EXPECT_EQ(Chain::takeEvents(c.robot_events), std::vector<std::string>{"e_ik_discontinuity"});
  KDL::Frame held;
  ASSERT_EQ(c.held.read(held), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(c.last(c.command), held, 1e-12)) << "the command is the held pose in the refusal's step";
  EXPECT_LT((held.p - before.p).Norm(), 1e-3);
  EXPECT_EQ(Chain::takeEvents(c.admittance_events), std::vector<std::string>{"e_resynced"});
  c.configurator.clock().advance(1ms);  // the generator takes the admittance's reference: at rest
  const std::vector<std::string> generator = Chain::takeEvents(c.generator_events);
  EXPECT_TRUE(contains(generator, "e_resynced") && contains(generator, "e_wait_path"));
  EXPECT_EQ(c.component("TrajGen").call<std::string>("status"), "WaitPath");
  // Held for 0.3 s: the command stays at the held pose, the robot settles there, nothing is refused
  // again, and nothing allocates.
  double worst_command = 0.0;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 300; ++i) {
                c.configurator.clock().advance(1ms);
                KDL::Frame f;
                (void)c.command.read(f);
                worst_command = std::max(worst_command, (f.p - held.p).Norm());
              }
            }),
            0);
  EXPECT_LT(worst_command, 1e-5) << "m: the command left the held pose";
  EXPECT_LT((c.last(c.measured).p - held.p).Norm(), 1e-4);
  EXPECT_EQ(Chain::takeEvents(c.robot_events), std::vector<std::string>{"e_ik_solved"});
  // Full speed again; the next motion (a path from the measured pose) starts at the held pose.
  c.component("Robot").setProperty("speed_scaling", 1.0);
  c.move("Path2");
  before = held;
  double worst_step = 0.0;
  for (int i = 0; i < 3000 && c.component("TrajGen").call<std::string>("status") == "Moving"; ++i) {
    const KDL::Frame f = c.last(c.command);
    worst_step = std::max(worst_step, (f.p - before.p).Norm());
    before = f;
    c.configurator.clock().advance(1ms);
  }
  EXPECT_LT(worst_step, 1e-3) << "m: the largest step of the command";
  EXPECT_EQ(c.component("TrajGen").call<std::string>("status"), "WaitPath");
  EXPECT_TRUE(Chain::takeEvents(c.robot_events).empty()) << "no command refused";
  c.configurator.clock().advance(200ms);
  const KDL::Vector goal = c.start.p + KDL::Vector(first[0] + second[0], first[1] + second[1], first[2] + second[2]);
  EXPECT_LT((c.last(c.measured).p - goal).Norm(), 1e-3) << "m: the second motion reached its goal from the held pose";
}

TEST(SimulatedRobotReSync, TheISURRefusingACommandMidMotionReSyncsItsCommandChain) {
  // The puncturing application's start (m, rad): the elbow on the IK's rule (q6 - q7 = 0.3 rad).
  checkRefusalReSyncsTheChain({"SimulatedISURRobot", "Robot.initial_joints = { 0.00202, 0.00249, 0.204398, 0, 0, 0.85, 0.55, 0 }"},
                              {0.02, 0.0, -0.01}, {0.0, 0.015, 0.0});
}

TEST(SimulatedRobotReSync, TheUR5RefusingACommandMidMotionReSyncsItsCommandChain) {
  checkRefusalReSyncsTheChain({"SimulatedUR5Robot", "Robot.initial_joints = { 0, -1.57, 1.57, -1.57, -1.57, 0 }"},
                              {0.03, 0.0, 0.0}, {0.0, -0.02, 0.01});
}

// The Puma 260's chain ends in the KinematicsSolver (apps/puma260: the solver refuses, the EtherCAT
// master's drives follow its joints); here the solver's joints are the measured ones, as a stiff
// position-controlled arm gives, starting at the task's ready position (rad).
TEST(SimulatedRobotReSync, ThePuma260sKinematicsSolverRefusingACommandMidMotionReSyncsItsCommandChain) {
  const RobotSpec puma{"KinematicsSolver",
                       "Robot.robot = 'puma260' Robot.max_joint_velocity = { 2, 2, 2, 2, 2, 2 }\n"
                       "Robot.tool_frame = { 0, 0, 0.118, 0, 0, 0, 1 }\n"
                       "connectPorts({ { output = 'Robot.desJointPositions', input = 'Robot.jointPositions' } })",
                       "desCartPose",
                       "cartPose",
                       "heldCartPose",
                       {0.4677, 1.2117, -3.2805, 0.0, -1.0727, -2.6740}};
  checkRefusalReSyncsTheChain(puma, {0.0, 0.03, 0.0}, {0.02, 0.0, -0.01});
}

}  // namespace
}  // namespace cobra::components::test
