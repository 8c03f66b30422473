// The simulated I-SUR and UR5 bridges on the lockstep clock: paths reproduced within the servo
// model's error, the sensor reading of the contact wrench, twist commands, property errors, and
// the continuity rule: commands across the I-SUR's wrist singularity or needing a UR5 wrist flip
// are refused with e_ik_discontinuity once, the robot holds, then follows again; no allocation.
#include "cobra/components/sim/simulated_robot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "puncturing_world.hpp"

namespace cobra::components::test {
namespace {

constexpr double kTau = 0.01;  // s, the components' default servo time constant

template <class Robot>
struct Rig {
  Robot robot{"robot"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> pose_command{"poseCommand", "", "m"};
  core::OutputPort<KDL::JntArray> joint_command{"jointCommand", "", "rad"};
  core::OutputPort<KDL::Wrench> contact{"contact", "", "N"};
  core::InputPort<KDL::Frame> pose{"pose", "", "m"};
  core::InputPort<KDL::JntArray> joints{"joints", "", "rad"};
  core::InputPort<KDL::Wrench> wrench{"wrench", "", "N"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit Rig(const KDL::Frame& base = KDL::Frame::Identity()) {
    robot.setProperty("base_frame", base);
    clock.add(robot, std::chrono::milliseconds(1));
    core::connectPorts(pose_command, robot.port("desCartPose"));
    core::connectPorts(joint_command, robot.port("desJointPosition"));
    core::connectPorts(contact, robot.port("contactWrench"));
    core::connectPorts(robot.port("measCartPose"), pose);
    core::connectPorts(robot.port("measJointPosition"), joints);
    core::connectPorts(robot.port("measWrench"), wrench);
    core::connectPorts(robot.port("events"), events, core::ConnPolicy::buffer(32));
  }
  void start() {
    ASSERT_TRUE(robot.configure()) << robot.lastError();
    ASSERT_TRUE(robot.start());
    clock.advance(std::chrono::milliseconds(1));
  }
  KDL::Frame measuredPose() {
    KDL::Frame f;
    EXPECT_NE(pose.read(f), core::FlowStatus::NoData);
    return f;
  }
  KDL::JntArray measuredJoints() {
    KDL::JntArray q;
    EXPECT_NE(joints.read(q), core::FlowStatus::NoData);
    return q;
  }
  /// Names of the events emitted since the last call.
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
};

/// The continuity rule on a simulated robot started at `initial` (rad, m): `refused` (a pose the
/// robot could only reach by swinging) sent every 1 ms step for 500 steps is refused with one
/// e_ik_discontinuity, the joints hold within one encoder count; then a pose 0.1 mm from the start
/// is followed, with e_ik_solved. `count_rad`, `count_m`: encoder resolution.
template <class Robot>
void checkRefusedThenFollowed(const std::vector<double>& initial, const KDL::Frame& refused, double count_rad,
                              double count_m) {
  Rig<Robot> rig;
  rig.robot.setProperty("initial_joints", initial);
  rig.start();
  const KDL::JntArray held = rig.measuredJoints();
  const KDL::Frame start = rig.measuredPose();
  for (int ms = 0; ms < 500; ++ms) {
    rig.pose_command.write(refused);
    rig.clock.advance(std::chrono::milliseconds(1));
    const KDL::JntArray q = rig.measuredJoints();
    for (unsigned j = 0; j < q.rows(); ++j)
      ASSERT_NEAR(q(j), held(j), j < 3 && count_m > 0.0 ? count_m : count_rad) << "joint " << j + 1 << " at " << ms;
  }
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_discontinuity"});
  KDL::Frame nearby = start;
  nearby.p += KDL::Vector(0.0, 0.0, 1e-4);
  rig.pose_command.write(nearby);
  rig.clock.advance(std::chrono::milliseconds(1));
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_solved"});
  for (int ms = 0; ms < 200; ++ms) rig.clock.advance(std::chrono::milliseconds(1));
  EXPECT_LT((rig.measuredPose().p - nearby.p).Norm(), 2e-5);
}

// A Cartesian line at constant speed v: the servo lags by at most v·τ (first-order lag of a ramp)
// plus the encoder resolution; after the end it settles on the target.
TEST(SimulatedISURRobot, FollowsACartesianPathWithinTheServoLag) {
  const KDL::Frame base(KDL::Rotation::RotZ(0.4), KDL::Vector(0.2, -0.1, 1.0));
  Rig<SimulatedISURRobot> rig(base);
  rig.start();
  const KDL::Frame start = rig.measuredPose();
  EXPECT_TRUE(KDL::Equal(start, base * isurStartPose(), 1e-4));
  const KDL::Vector direction = KDL::Vector(1.0, -0.5, -0.8) / KDL::Vector(1.0, -0.5, -0.8).Norm();
  const double speed = 0.02;  // m/s
  double worst = 0.0;
  for (int ms = 1; ms <= 2000; ++ms) {
    KDL::Frame target = start;
    target.p += direction * (speed * ms * 1e-3);
    rig.pose_command.write(target);
    rig.clock.advance(std::chrono::milliseconds(1));
    const KDL::Frame measured = rig.measuredPose();
    if (ms > 100) worst = std::max(worst, (measured.p - target.p).Norm());
    EXPECT_LT(KDL::diff(measured.M, target.M).Norm(), 1e-3) << ms;
  }
  EXPECT_LT(worst, speed * kTau * 1.2 + 2e-5);
  EXPECT_GT(worst, speed * kTau * 0.5);  // it does lag: a first-order servo, not a teleport
  for (int ms = 0; ms < 200; ++ms) rig.clock.advance(std::chrono::milliseconds(1));
  KDL::Frame end = start;
  end.p += direction * (speed * 2.0);
  EXPECT_LT((rig.measuredPose().p - end.p).Norm(), 2e-5);
}

TEST(SimulatedISURRobot, JointCommandsAreClampedToTheLimitsAndVelocity) {
  Rig<SimulatedISURRobot> rig;
  rig.start();
  KDL::JntArray q = jointArray({0.1, 0.1, 0.1, 0.0, 0.0, 0.6, 0.6, 0.0});
  q(0) = 0.15;  // 50 mm on slider 1: at 0.1 m/s this takes 0.5 s at least
  q(3) = 10.0;  // beyond the base joint's 2.967 rad limit
  rig.joint_command.write(q);
  rig.clock.advance(std::chrono::milliseconds(100));
  KDL::JntArray measured;
  ASSERT_NE(rig.joints.read(measured), core::FlowStatus::NoData);
  EXPECT_NEAR(measured(0), 0.1 + 0.1 * 0.1, 1e-4);  // velocity-limited
  for (int i = 0; i < 5; ++i) rig.clock.advance(std::chrono::seconds(1));
  ASSERT_NE(rig.joints.read(measured), core::FlowStatus::NoData);
  EXPECT_NEAR(measured(0), 0.15, 2e-6);
  EXPECT_NEAR(measured(3), 2.967, 1e-4);
}

TEST(SimulatedISURRobot, AnUnreachablePoseHoldsTheLastCommandAndSaysSo) {
  Rig<SimulatedISURRobot> rig;
  rig.start();
  const KDL::Frame start = rig.measuredPose();
  rig.pose_command.write(KDL::Frame(start.M, start.p + KDL::Vector(0, 0, 5.0)));  // 5 m up
  rig.clock.advance(std::chrono::milliseconds(100));
  EXPECT_LT((rig.measuredPose().p - start.p).Norm(), 1e-4);
  core::Event e;
  ASSERT_EQ(rig.events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_ik_failed");
  rig.pose_command.write(start);
  rig.clock.advance(std::chrono::milliseconds(1));
  ASSERT_EQ(rig.events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_ik_solved");
}

// A broken command chain writes NaN and inf poses and joints: none reaches the servo, the robot
// holds its last valid command, e_command_not_finite is told once per episode (not per sample),
// nothing is allocated, and the next valid command is followed.
TEST(SimulatedISURRobot, ANonFiniteCommandNeverReachesTheServoAndIsToldOncePerEpisode) {
  Rig<SimulatedISURRobot> rig;
  rig.start();
  const KDL::Frame start = rig.measuredPose();
  KDL::Frame target = start;
  for (int ms = 1; ms <= 50; ++ms) {  // moving at 0.02 m/s
    target.p += KDL::Vector(2e-5, 0.0, 0.0);
    rig.pose_command.write(target);
    rig.clock.advance(std::chrono::milliseconds(1));
  }
  (void)rig.takeEvents();
  const KDL::JntArray last_joints = rig.measuredJoints();
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    KDL::Frame broken = target;
    broken.p.z(bad);
    KDL::JntArray broken_joints = last_joints;
    broken_joints(2) = bad;
    long allocations = 0;
    for (int ms = 0; ms < 200; ++ms) {
      // Counted once the test's own joint port has sized its connection's slots (its first writes).
      const long during = cobra::test_support::allocationsDuring([&] {
        if (ms % 2 == 0) rig.pose_command.write(broken);
        else rig.joint_command.write(broken_joints);
        rig.clock.advance(std::chrono::milliseconds(1));
      });
      if (ms >= 10) allocations += during;
    }
    EXPECT_EQ(allocations, 0);
    const KDL::Frame held = rig.measuredPose();
    EXPECT_LT((held.p - target.p).Norm(), 2e-5);  // at the last valid command (the lag has settled)
    EXPECT_EQ(rig.takeEvents(), (std::vector<std::string>{"e_command_not_finite"}));
    target.p += KDL::Vector(2e-5, 0.0, 0.0);  // a valid command again: followed, the episode over
    for (int ms = 0; ms < 100; ++ms) {
      rig.pose_command.write(target);
      rig.clock.advance(std::chrono::milliseconds(1));
    }
    EXPECT_LT((rig.measuredPose().p - target.p).Norm(), 2e-5);
    EXPECT_TRUE(rig.takeEvents().empty());
  }
}

// The sensor reads the world-frame contact wrench in the tool frame (Nano17 noise ~3 mN).
TEST(SimulatedISURRobot, TheSensorReadsTheContactWrenchInTheToolFrame) {
  Rig<SimulatedISURRobot> rig;
  rig.start();
  const KDL::Frame tool = rig.measuredPose();
  const KDL::Wrench world_wrench(KDL::Vector(1.0, -2.0, 3.0), KDL::Vector::Zero());
  rig.contact.write(world_wrench);
  rig.clock.advance(std::chrono::milliseconds(2));
  KDL::Wrench read;
  ASSERT_NE(rig.wrench.read(read), core::FlowStatus::NoData);
  const KDL::Wrench expected = tool.M.Inverse() * world_wrench;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(read.force(i), expected.force(i), 0.02) << i;
  rig.contact.write(KDL::Wrench(KDL::Vector(0, 0, 1000.0), KDL::Vector::Zero()));  // beyond the overload
  rig.clock.advance(std::chrono::milliseconds(1));
  ASSERT_NE(rig.wrench.read(read), core::FlowStatus::NoData);
  EXPECT_LE(std::abs(read.force.x()), 250.0 + 1e-9);
  EXPECT_LE(std::abs(read.force.z()), 480.0 + 1e-9);
}

TEST(SimulatedUR5Robot, FollowsJointAndTwistCommands) {
  Rig<SimulatedUR5Robot> rig;
  core::OutputPort<KDL::Twist> twist_command{"twistCommand", "", "m/s"};
  core::InputPort<KDL::Twist> twist{"twist", "", "m/s"};
  core::connectPorts(twist_command, rig.robot.port("desTwist"));
  core::connectPorts(rig.robot.port("measTwist"), twist);
  rig.start();
  // A joint ramp of 0.5 rad/s on joint 1, commanded each 1 ms step: the exact first-order response
  // settles on a lag of v·dt·a/(1 - a), a = exp(-dt/τ) (v·τ in continuous time), plus one encoder count.
  const double a = std::exp(-1e-3 / kTau);
  const double lag = 0.5 * 1e-3 * a / (1.0 - a);
  KDL::JntArray q = jointArray({0.0, -1.57, 1.57, -1.57, -1.57, 0.0});
  for (int ms = 1; ms <= 500; ++ms) {
    q(0) = 0.5 * ms * 1e-3;
    rig.joint_command.write(q);
    rig.clock.advance(std::chrono::milliseconds(1));
    KDL::JntArray measured;
    ASSERT_NE(rig.joints.read(measured), core::FlowStatus::NoData);
    if (ms > 100) {
      EXPECT_NEAR(measured(0), q(0) - lag, 2.0 * 3.1416 / 262144) << ms;
    }
  }
  for (int ms = 0; ms < 200; ++ms) rig.clock.advance(std::chrono::milliseconds(1));
  // A twist of 20 mm/s along world y, sent every step for 0.5 s: 10 mm, measured back as a twist.
  const KDL::Frame before = rig.measuredPose();
  KDL::Twist measured_twist;
  for (int ms = 0; ms < 500; ++ms) {
    twist_command.write(KDL::Twist(KDL::Vector(0, 0.02, 0), KDL::Vector::Zero()));
    rig.clock.advance(std::chrono::milliseconds(1));
    ASSERT_NE(twist.read(measured_twist), core::FlowStatus::NoData);
  }
  EXPECT_NEAR(measured_twist.vel.y(), 0.02, 0.002);
  // The last twist stops after twist_timeout (0.1 s): the pose settles 10 mm further.
  for (int ms = 0; ms < 400; ++ms) rig.clock.advance(std::chrono::milliseconds(1));
  const KDL::Frame after = rig.measuredPose();
  EXPECT_NEAR(after.p.y() - before.p.y(), 0.01 + 0.02 * 0.1, 1e-4);
  EXPECT_NEAR(after.p.x(), before.p.x(), 1e-4);
  EXPECT_LT(KDL::diff(after.M, before.M).Norm(), 1e-4);
}

TEST(SimulatedISURRobot, ACommandAcrossTheWristSingularityIsRefusedOnceAndTheRobotHolds) {
  // Needle 0.3° short of vertical (pitch q6 + q7 = 90° - 0.005 rad, the elbow q6 - q7 on the
  // solver's rule); the command tilts it 0.3° past: on the robot's branch, yaw and roll would turn
  // by π.
  const double elbow = kinematics::IsurGeometry{}.pitch_difference;
  const double pitch = std::numbers::pi / 2 - 0.005;
  const std::vector<double> initial{0.1, 0.1, 0.1, 0.0, 0.0, 0.5 * (pitch + elbow), 0.5 * (pitch - elbow), 0.0};
  KDL::JntArray across = jointArray(initial);
  across(5) += 0.005;
  across(6) += 0.005;
  kinematics::IsurPuncturingSolver isur;
  KDL::Frame refused;
  ASSERT_EQ(isur.forward(across, refused), kinematics::IkStatus::Ok);
  checkRefusedThenFollowed<SimulatedISURRobot>(initial, refused, 2 * std::numbers::pi / 262144, 1e-6);
}

TEST(SimulatedUR5Robot, APoseThatNeedsAWristFlipIsRefusedOnceAndTheRobotHolds) {
  // Wrist 0.01 rad from its singularity; the command's nearest joints are 0.01 rad on the other
  // side (the wrist flipped): on the robot's branch q4 and q6 would turn by π.
  const std::vector<double> initial{0.1, -1.3, 1.5, -1.7, 0.01, 0.3};
  KDL::JntArray across = jointArray(initial);
  across(4) = -0.01;
  kinematics::Ur5Solver ur5;
  KDL::Frame refused;
  ASSERT_EQ(ur5.forward(across, refused), kinematics::IkStatus::Ok);
  checkRefusedThenFollowed<SimulatedUR5Robot>(initial, refused, 2 * std::numbers::pi / 262144, 0.0);
}

TEST(SimulatedUR5Robot, CartesianCommandsAcceptedOrRefusedAllocateNothing) {
  Rig<SimulatedUR5Robot> rig;
  rig.start();
  const KDL::Frame start = rig.measuredPose();
  KDL::Frame far = start;
  far.p += KDL::Vector(0.1, 0.0, 0.0);  // 10 cm in 1 ms
  (void)rig.takeEvents();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int ms = 0; ms < 100; ++ms) {
                KDL::Frame target = start;
                target.p += KDL::Vector(0.0, 1e-5 * ms, 0.0);
                rig.pose_command.write(ms % 10 == 5 ? far : target);
                rig.clock.advance(std::chrono::milliseconds(1));
              }
            }),
            0);
  const std::vector<std::string> events = rig.takeEvents();
  ASSERT_EQ(events.size(), 20u);  // 10 refusal episodes, each: refused, then accepted again
  for (std::size_t i = 0; i < events.size(); ++i)
    EXPECT_EQ(events[i], i % 2 == 0 ? "e_ik_discontinuity" : "e_ik_solved") << i;
}

TEST(SimulatedRobots, BadPropertiesAreRefusedWithTheirNameAndWhatIsExpected) {
  SimulatedISURRobot isur("isur");
  isur.setProperty("initial_joints", std::vector<double>{0.1, 0.1, 0.1, 0.0, 0.0, 0.6});
  core::Result r = isur.configure();
  EXPECT_FALSE(r);
  EXPECT_EQ(r.message,
            "component 'isur': property initial_joints has 6 values; the I-SUR has 8 joints: give one position per "
            "joint (rad, m for prismatic joints)");

  SimulatedUR5Robot ur5("ur5");
  ur5.setProperty("max_velocity", std::vector<double>{1.0, 1.0});
  r = ur5.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property max_velocity has 2 values; the UR5 has 6 joints");

  SimulatedUR5Robot sensor("ur5");
  sensor.setProperty("sensor", std::string("nano99"));
  r = sensor.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property sensor is 'nano99'; expected atiNano17, atiNano43 or ftSens");

  SimulatedUR5Robot lag("ur5");
  lag.setProperty("time_constant", 0.0);
  r = lag.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property time_constant is 0.000000 s; expected > 0 s");
}

}  // namespace
}  // namespace cobra::components::test
