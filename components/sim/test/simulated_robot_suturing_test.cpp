// The simulated two-armed I-SUR (SimulatedISURSuturingRobot) on the lockstep clock: its fixed
// interface, both tools following Cartesian commands solved together by the split IK (a tool not
// commanded holds its pose while the macro moves under it), refusals as the single-tool robots
// (the Endo Stitch across its wrist singularity, the gripper arm's wrist flip, out of reach), the
// two sensors, the Endo Stitch actuation, property errors, registration, and no allocation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>
#include <numbers>
#include <string>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/sim/simulated_robot.hpp"
#include "cobra/deploy/package_registry.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "puncturing_world.hpp"

namespace cobra::components::test {
namespace {

const std::vector<double> kInitial{0.1, 0.1, 0.1, 0.0, 0.0, 0.75, 0.45, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0};
constexpr double kRevoluteCount = 2 * std::numbers::pi / 262144;  // rad, one encoder count
constexpr double kSliderCount = 1e-6;                               // m

struct SuturingRig {
  SimulatedISURSuturingRobot robot{"isur"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> right_command{"rightCommand", "", "m"};
  core::OutputPort<KDL::Frame> left_command{"leftCommand", "", "m"};
  core::OutputPort<KDL::Wrench> right_contact{"rightContact", "", "N"};
  core::OutputPort<KDL::Wrench> left_contact{"leftContact", "", "N"};
  core::OutputPort<core::Event> requests{"requests", "", ""};
  core::InputPort<KDL::Frame> right_pose{"rightPose", "", "m"};
  core::InputPort<KDL::Frame> left_pose{"leftPose", "", "m"};
  core::InputPort<KDL::Frame> right_true{"rightTrue", "", "m"};
  core::InputPort<KDL::Wrench> right_wrench{"rightWrench", "", "N"};
  core::InputPort<KDL::Wrench> left_wrench{"leftWrench", "", "N"};
  core::InputPort<KDL::JntArray> joints{"joints", "", "rad"};
  core::InputPort<int> actuations{"actuations", "", "1"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit SuturingRig(const KDL::Frame& base = KDL::Frame::Identity()) {
    robot.setProperty("base_frame", base);
    clock.add(robot, std::chrono::milliseconds(1));
    core::connectPorts(right_command, robot.port("desRightCartPose"));
    core::connectPorts(left_command, robot.port("desLeftCartPose"));
    core::connectPorts(right_contact, robot.port("contactRightWrench"));
    core::connectPorts(left_contact, robot.port("contactLeftWrench"));
    core::connectPorts(requests, robot.port("inputEvents"), core::ConnPolicy::buffer(8));
    core::connectPorts(robot.port("measRightCartPose"), right_pose);
    core::connectPorts(robot.port("measLeftCartPose"), left_pose);
    core::connectPorts(robot.port("trueRightCartPose"), right_true);
    core::connectPorts(robot.port("measRightWrench"), right_wrench);
    core::connectPorts(robot.port("measLeftWrench"), left_wrench);
    core::connectPorts(robot.port("measJointPosition"), joints);
    core::connectPorts(robot.port("endoStitchActuations"), actuations);
    core::connectPorts(robot.port("events"), events, core::ConnPolicy::buffer(256));
  }
  void start() {
    ASSERT_TRUE(robot.configure()) << robot.lastError();
    ASSERT_TRUE(robot.start());
    step();
  }
  void step(int ms = 1) {
    for (int i = 0; i < ms; ++i) clock.advance(std::chrono::milliseconds(1));
  }
  template <class T>
  T latest(core::InputPort<T>& port) {
    T value{};
    EXPECT_NE(port.read(value), core::FlowStatus::NoData) << port.name();
    return value;
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
};

/// Largest joint difference, in encoder counts (sliders: 1 µm, revolute: 2^-18 rev).
double countsApart(const KDL::JntArray& a, const KDL::JntArray& b) {
  double worst = 0.0;
  for (unsigned j = 0; j < a.rows(); ++j)
    worst = std::max(worst, std::abs(a(j) - b(j)) / (j < 3 ? kSliderCount : kRevoluteCount));
  return worst;
}

TEST(SimulatedISURSuturingRobot, HasTheTwoToolInterface) {
  SimulatedISURSuturingRobot robot("isur");
  for (const char* port : {"desJointPosition", "measJointPosition", "desRightCartPose", "measRightCartPose",
                           "trueRightCartPose", "measRightWrench", "contactRightWrench", "desLeftCartPose",
                           "measLeftCartPose", "trueLeftCartPose", "measLeftWrench", "contactLeftWrench",
                           "inputEvents", "endoStitchActuations", "events"})
    EXPECT_NE(robot.findPort(port), nullptr) << port;
  EXPECT_EQ(robot.getProperty<std::string>("right_sensor"), "atiNano43");
  EXPECT_EQ(robot.getProperty<std::string>("left_sensor"), "atiNano17");
  EXPECT_EQ(robot.getProperty<std::string>("actuate_event"), "e_actuate_endo_stitch");
  EXPECT_DOUBLE_EQ(robot.getProperty<double>("actuation_time"), 0.3);
  EXPECT_EQ(robot.getProperty<std::vector<double>>("initial_joints"), kInitial);
  for (const char* property : {"base_frame", "right_tool_frame", "left_tool_frame", "time_constant", "max_velocity",
                               "encoder_counts", "right_sensor_bias", "left_sensor_bias", "sensor_cutoff", "seed"})
    EXPECT_NE(robot.findProperty(property), nullptr) << property;
}

// The Endo Stitch moves 20 mm along a slanted line at 20 mm/s with the same orientation: only
// the macro can translate it, so the platform moves, and the gripper (never commanded) holds its
// pose: its arm compensates. Then the gripper moves and the Endo Stitch holds.
TEST(SimulatedISURSuturingRobot, EachToolFollowsItsCommandWhileTheOtherHolds) {
  const KDL::Frame base(KDL::Rotation::RotZ(0.3), KDL::Vector(0.1, 0.0, 1.0));
  SuturingRig rig(base);
  rig.start();
  kinematics::IsurSuturingSolver solver;
  KDL::Frame stitch_fk, gripper_fk;
  ASSERT_EQ(solver.forward(jointArray(kInitial), stitch_fk, gripper_fk), kinematics::IkStatus::Ok);
  const KDL::Frame right0 = rig.latest(rig.right_pose), left0 = rig.latest(rig.left_pose);
  EXPECT_TRUE(KDL::Equal(right0, base * stitch_fk, 1e-4));
  EXPECT_TRUE(KDL::Equal(left0, base * gripper_fk, 1e-4));
  const KDL::JntArray q0 = rig.latest(rig.joints);

  const KDL::Vector direction = KDL::Vector(1.0, -0.5, -0.8) / KDL::Vector(1.0, -0.5, -0.8).Norm();
  const double speed = 0.02;  // m/s
  double worst_left = 0.0;
  for (int ms = 1; ms <= 1000; ++ms) {
    KDL::Frame target = right0;
    target.p += direction * (speed * ms * 1e-3);
    rig.right_command.write(target);
    rig.step();
    worst_left = std::max(worst_left, (rig.latest(rig.left_pose).p - left0.p).Norm());
  }
  rig.step(200);
  KDL::Frame end = right0;
  end.p += direction * 0.02;
  EXPECT_LT((rig.latest(rig.right_pose).p - end.p).Norm(), 2e-5);
  EXPECT_LT(KDL::diff(rig.latest(rig.right_pose).M, right0.M).Norm(), 1e-4);
  // While the platform moved 20 mm the gripper stayed within the servo lag of its arm's joints.
  EXPECT_LT(worst_left, 5e-4);
  EXPECT_LT((rig.latest(rig.left_pose).p - left0.p).Norm(), 5e-5);
  EXPECT_LT(KDL::diff(rig.latest(rig.left_pose).M, left0.M).Norm(), 1e-3);
  const KDL::JntArray q1 = rig.latest(rig.joints);
  EXPECT_GT(std::abs(q1(0) - q0(0)) + std::abs(q1(1) - q0(1)) + std::abs(q1(2) - q0(2)), 5e-3);  // the macro moved
  double left_arm_motion = 0.0;
  for (unsigned j = 8; j < 14; ++j) left_arm_motion += std::abs(q1(j) - q0(j));
  EXPECT_GT(left_arm_motion, 0.01);  // and the 6-DOF arm compensated

  const KDL::Frame right1 = rig.latest(rig.right_pose);
  KDL::Frame left_target = left0;
  for (int ms = 1; ms <= 500; ++ms) {
    left_target = KDL::Frame(KDL::Rotation::RotX(0.2 * ms * 1e-3) * left0.M,
                             left0.p + KDL::Vector(0.0, 0.01, 0.01) * (ms * 2e-3));
    rig.left_command.write(left_target);
    rig.step();
  }
  rig.step(200);
  EXPECT_TRUE(KDL::Equal(rig.latest(rig.left_pose), left_target, 5e-5));
  EXPECT_LT((rig.latest(rig.right_pose).p - right1.p).Norm(), 2e-5);
  const KDL::JntArray q2 = rig.latest(rig.joints);
  for (unsigned j = 0; j < 8; ++j) EXPECT_LE(std::abs(q2(j) - q1(j)), j < 3 ? kSliderCount : kRevoluteCount) << j;
  EXPECT_TRUE(rig.takeEvents().empty());
}

/// Refusal as the single-tool robots: `refused` commanded on `tool` (0 right, 1 left) every 1 ms
/// step for 300 steps from `initial` gives one e_ik_discontinuity, every joint holds within an
/// encoder count, and each step's heldRightCartPose and heldLeftCartPose are the poses both tools
/// hold (for the producers of their commands to re-sync to); then a pose 0.1 mm from the start is
/// followed, with e_ik_solved, and nothing is held any more.
void checkRefusedThenFollowed(const std::vector<double>& initial, int tool, const KDL::Frame& refused) {
  SuturingRig rig;
  core::InputPort<KDL::Frame> held_right{"heldRight", "", "m"}, held_left{"heldLeft", "", "m"};
  core::connectPorts(rig.robot.port("heldRightCartPose"), held_right);
  core::connectPorts(rig.robot.port("heldLeftCartPose"), held_left);
  rig.robot.setProperty("initial_joints", initial);
  rig.start();
  const KDL::JntArray held = rig.latest(rig.joints);
  core::OutputPort<KDL::Frame>& command = tool == 0 ? rig.right_command : rig.left_command;
  core::InputPort<KDL::Frame>& pose = tool == 0 ? rig.right_pose : rig.left_pose;
  const KDL::Frame start = rig.latest(pose);
  const KDL::Frame right0 = rig.latest(rig.right_pose), left0 = rig.latest(rig.left_pose);
  KDL::Frame f;
  EXPECT_EQ(held_right.read(f), core::FlowStatus::NoData);
  for (int ms = 0; ms < 300; ++ms) {
    command.write(refused);
    rig.step();
    ASSERT_LE(countsApart(rig.latest(rig.joints), held), 1.0) << ms;
    ASSERT_EQ(held_right.read(f), core::FlowStatus::NewData) << ms;
    ASSERT_TRUE(KDL::Equal(f.p, right0.p, 1e-5)) << ms;  // m: the encoders' pose of the held joints
    ASSERT_EQ(held_left.read(f), core::FlowStatus::NewData) << ms;
    ASSERT_TRUE(KDL::Equal(f.p, left0.p, 1e-5)) << ms;
  }
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_discontinuity"});
  KDL::Frame nearby = start;
  nearby.p += KDL::Vector(0.0, 0.0, 1e-4);
  command.write(nearby);
  rig.step();
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_solved"});
  rig.step(200);
  EXPECT_LT((rig.latest(pose).p - nearby.p).Norm(), 2e-5);
  EXPECT_EQ(held_right.read(f), core::FlowStatus::OldData);
}

TEST(SimulatedISURSuturingRobot, TheEndoStitchAcrossItsWristSingularityIsRefusedOnce) {
  // The Endo Stitch 0.3° short of vertical (pitch q6 + q7 = 90° - 0.005 rad, elbow on the rule);
  // the command tilts it 0.3° past: on the robot's branch yaw and roll would turn by π.
  const double elbow = kinematics::IsurGeometry{}.pitch_difference;
  const double pitch = std::numbers::pi / 2 - 0.005;
  std::vector<double> initial = kInitial;
  initial[5] = 0.5 * (pitch + elbow);
  initial[6] = 0.5 * (pitch - elbow);
  KDL::JntArray across = jointArray(initial);
  across(5) += 0.005;
  across(6) += 0.005;
  kinematics::IsurSuturingSolver solver;
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(across, stitch, gripper), kinematics::IkStatus::Ok);
  checkRefusedThenFollowed(initial, 0, stitch);
}

TEST(SimulatedISURSuturingRobot, AGripperPoseThatNeedsAWristFlipIsRefusedOnce) {
  // The 6-DOF arm's wrist 0.01 rad from alignment (q13); the command's nearest joints are 0.01 rad
  // on the other side: on the robot's branch q12 and q14 would turn by π.
  std::vector<double> initial = kInitial;
  initial[12] = 0.01;
  KDL::JntArray across = jointArray(initial);
  across(12) = -0.01;
  kinematics::IsurSuturingSolver solver;
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(across, stitch, gripper), kinematics::IkStatus::Ok);
  checkRefusedThenFollowed(initial, 1, gripper);
}

TEST(SimulatedISURSuturingRobot, AnUnreachableToolPoseHoldsBothArmsAndSaysSo) {
  SuturingRig rig;
  rig.start();
  const KDL::JntArray held = rig.latest(rig.joints);
  const KDL::Frame left0 = rig.latest(rig.left_pose);
  rig.left_command.write(KDL::Frame(left0.M, left0.p + KDL::Vector(0.0, 0.0, 2.0)));  // 2 m away
  rig.step(50);
  EXPECT_LE(countsApart(rig.latest(rig.joints), held), 1.0);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_failed"});
  // The right tool's command in the same episode is solved with the left tool's last valid pose.
  KDL::Frame right = rig.latest(rig.right_pose);
  right.p += KDL::Vector(0.0, 0.0, -1e-4);
  rig.right_command.write(right);
  rig.step(200);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_solved"});
  EXPECT_LT((rig.latest(rig.right_pose).p - right.p).Norm(), 2e-5);
  EXPECT_LT((rig.latest(rig.left_pose).p - left0.p).Norm(), 5e-5);
}

// Each tool's sensor reads its own contact wrench in its tool frame (Nano43 ~ 6 mN noise, Nano17
// ~ 3 mN); the Nano17 saturates at 250 N (x), the Nano43 at 36 N.
TEST(SimulatedISURSuturingRobot, EachSensorReadsItsToolsContactWrenchInTheToolFrame) {
  SuturingRig rig;
  rig.start();
  const KDL::Frame right = rig.latest(rig.right_pose), left = rig.latest(rig.left_pose);
  const KDL::Wrench on_right(KDL::Vector(1.0, -2.0, 3.0), KDL::Vector::Zero());
  const KDL::Wrench on_left(KDL::Vector(-0.5, 0.0, 2.0), KDL::Vector::Zero());
  rig.right_contact.write(on_right);
  rig.left_contact.write(on_left);
  rig.step(2);
  const KDL::Wrench right_read = rig.latest(rig.right_wrench), left_read = rig.latest(rig.left_wrench);
  const KDL::Wrench right_expected = right.M.Inverse() * on_right, left_expected = left.M.Inverse() * on_left;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(right_read.force(i), right_expected.force(i), 0.05) << i;
    EXPECT_NEAR(left_read.force(i), left_expected.force(i), 0.05) << i;
  }
}

TEST(SimulatedISURSuturingRobot, AnActuationCompletesAfterActuationTimeAndABusyRequestIsRefused) {
  SuturingRig rig;
  rig.start();
  EXPECT_EQ(rig.latest(rig.actuations), 0);
  core::Event request;
  request.name = "e_actuate_endo_stitch";
  rig.requests.write(request);
  rig.step();  // taken in this step: completes 0.3 s later
  rig.step(100);
  rig.requests.write(request);  // during the actuation: refused
  core::Event other;
  other.name = "e_something_else";
  rig.requests.write(other);  // ignored
  rig.step();
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_endo_stitch_busy"});
  rig.step(198);  // 299 ms after the step that took the request
  EXPECT_EQ(rig.latest(rig.actuations), 0);
  EXPECT_TRUE(rig.takeEvents().empty());
  rig.step();  // 300 ms after it
  EXPECT_EQ(rig.latest(rig.actuations), 1);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_endo_stitch_actuated"});
  rig.requests.write(request);  // a new one is accepted once done
  rig.step(301);
  EXPECT_EQ(rig.latest(rig.actuations), 2);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_endo_stitch_actuated"});
}

TEST(SimulatedISURSuturingRobot, TheActuationEventAndTimeAreProperties) {
  SuturingRig rig;
  rig.robot.setProperty("actuate_event", std::string("e_stitch"));
  rig.robot.setProperty("actuation_time", 0.05);
  rig.start();
  core::Event request;
  request.name = "e_actuate_endo_stitch";  // not this robot's event any more
  rig.requests.write(request);
  rig.step(100);
  EXPECT_EQ(rig.latest(rig.actuations), 0);
  request.name = "e_stitch";
  rig.requests.write(request);
  rig.step(50);
  EXPECT_EQ(rig.latest(rig.actuations), 0);
  rig.step();
  EXPECT_EQ(rig.latest(rig.actuations), 1);
}

TEST(SimulatedISURSuturingRobot, UpdatesAllocateNothing) {
  SuturingRig rig;
  rig.start();
  const KDL::Frame right0 = rig.latest(rig.right_pose), left0 = rig.latest(rig.left_pose);
  KDL::Frame far = right0;
  far.p += KDL::Vector(0.1, 0.0, 0.0);  // 10 cm in 1 ms: refused
  core::Event request;
  request.name = "e_actuate_endo_stitch";
  (void)rig.takeEvents();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int ms = 0; ms < 400; ++ms) {
                KDL::Frame right = right0, left = left0;
                right.p += KDL::Vector(0.0, 1e-5 * ms, 0.0);
                left.p += KDL::Vector(-1e-5 * ms, 0.0, 0.0);
                rig.right_command.write(ms % 10 == 5 ? far : right);
                if (ms % 2 == 0) rig.left_command.write(left);
                rig.right_contact.write(KDL::Wrench(KDL::Vector(0.1, 0.0, 0.0), KDL::Vector::Zero()));
                if (ms % 100 == 0) rig.requests.write(request);
                rig.step();
              }
            }),
            0);
  // Requests at 0 (taken), 100 and 200 ms (busy), 300 ms (the first completes, this one is taken).
  int refused = 0, solved = 0, actuated = 0, busy = 0;
  for (const std::string& e : rig.takeEvents()) {
    refused += e == "e_ik_discontinuity" || e == "e_ik_failed" ? 1 : 0;
    solved += e == "e_ik_solved" ? 1 : 0;
    actuated += e == "e_endo_stitch_actuated" ? 1 : 0;
    busy += e == "e_endo_stitch_busy" ? 1 : 0;
  }
  EXPECT_EQ(refused, 40);  // 40 refusal episodes, each refused, then accepted again
  EXPECT_EQ(solved, 40);
  EXPECT_EQ(actuated, 1);
  EXPECT_EQ(busy, 2);
  EXPECT_EQ(rig.latest(rig.actuations), 1);
}

/// `a` to `b` at `s` in [0, 1]: the position on the line, the rotation on the geodesic (what the
/// Cartesian trajectory generator follows between two waypoints).
KDL::Frame interpolate(const KDL::Frame& a, const KDL::Frame& b, double s) {
  KDL::Vector axis;
  const double angle = (a.M.Inverse() * b.M).GetRotAngle(axis);
  return KDL::Frame(angle > 0.0 ? a.M * KDL::Rotation::Rot2(axis, s * angle) : a.M, a.p + (b.p - a.p) * s);
}

// The planner (planning::MotionPlanner on planning/test/scenes/suturing.scene, joint space from the
// robot's joints) and the robot agree: the planned Cartesian waypoints, commanded every 1 ms at
// the planner's generator speeds (each segment at least as long as the planner assumed), are
// followed with no refusal (no e_ik_* event: no branch change, no joint beyond its speed), the
// Endo Stitch passing through its vertical between the two crossing waypoints, and the robot ends
// on the planned goal joints.
TEST(SimulatedISURSuturingRobot, APlannedPathThroughTheEndoStitchsVerticalIsFollowedWithoutARefusal) {
  planning::SceneDescription scene =
      planning::loadScene(std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes/suturing.scene");
  const KDL::Frame base = scene.robots[0].base_in_world;
  planning::RobotModels models = planning::makeRobotModels(scene);
  planning::StateValidator validator(std::move(scene), std::move(models));
  planning::PlannerOptions options;
  options.first_bounds = {{-0.8, -0.8, 0.0}, {0.8, 0.8, 1.2}};
  options.second_bounds = options.first_bounds;
  options.max_validity_checks = 100000;
  options.max_linear_velocity = 0.04;   // m/s
  options.max_angular_velocity = 0.15;  // rad/s
  planning::MotionPlanner planner(validator, options);
  // The goal: the Endo Stitch pitched past its vertical (1.9 rad), turned and rolled, the
  // gripper arm moved on its branch, the platform shifted.
  const planning::JointState start(kInitial.begin(), kInitial.end());
  const planning::JointState goal_joints{0.12, 0.09, 0.11, 0.0, 0.6, 1.1, 0.8, 0.5, 0.4, 0.2, -0.2, 0.5, 0.9, -0.5};
  planning::DualPose goal;
  ASSERT_TRUE(validator.toolPoses(goal_joints, goal));
  const planning::PlanResult plan = planner.planPath(start, goal);
  ASSERT_TRUE(plan.solved()) << plan.message;
  bool crossed = false;
  for (const planning::JointState& q : plan.joint_waypoints) crossed = crossed || q[5] + q[6] > std::numbers::pi / 2;
  EXPECT_TRUE(crossed);

  SuturingRig rig(base);
  rig.start();
  (void)rig.takeEvents();
  double worst_right = 0.0, worst_left = 0.0;  // m, commanded to measured
  for (std::size_t k = 0; k + 1 < plan.waypoints.size(); ++k) {
    const planning::DualPose& a = plan.waypoints[k];
    const planning::DualPose& b = plan.waypoints[k + 1];
    double duration = options.blend_time;
    for (const auto& [from, to] : {std::pair{&a.first, &b.first}, std::pair{&a.second, &b.second}}) {
      for (int i = 0; i < 3; ++i)
        duration = std::max(duration, std::abs(to->p(i) - from->p(i)) / options.max_linear_velocity);
      KDL::Vector axis;
      duration = std::max(duration, (from->M.Inverse() * to->M).GetRotAngle(axis) / options.max_angular_velocity);
    }
    const int steps = static_cast<int>(std::ceil(duration / 1e-3));
    for (int i = 1; i <= steps; ++i) {
      const double s = static_cast<double>(i) / steps;
      const KDL::Frame right = interpolate(a.first, b.first, s), left = interpolate(a.second, b.second, s);
      rig.right_command.write(right);
      rig.left_command.write(left);
      rig.step();
      worst_right = std::max(worst_right, (rig.latest(rig.right_pose).p - right.p).Norm());
      worst_left = std::max(worst_left, (rig.latest(rig.left_pose).p - left.p).Norm());
    }
    ASSERT_TRUE(rig.takeEvents().empty()) << "segment " << k << " of " << plan.waypoints.size() - 1;
  }
  rig.step(200);
  const KDL::JntArray q = rig.latest(rig.joints);
  for (unsigned j = 0; j < 14; ++j) EXPECT_NEAR(q(j), plan.joint_waypoints.back()[j], 1e-4) << "joint " << j + 1;
  // The servo lags its command by speed x time constant: 0.04 m/s x 0.01 s per axis, plus the
  // platform's share of a rotation.
  EXPECT_LT(worst_right, 2e-3);
  EXPECT_LT(worst_left, 2e-3);
  RecordProperty("waypoints", static_cast<int>(plan.waypoints.size()));
  RecordProperty("worst_tracking_right_m", std::to_string(worst_right));
  RecordProperty("worst_tracking_left_m", std::to_string(worst_left));
}

TEST(SimulatedISURSuturingRobot, BadPropertiesAreRefusedWithTheirNameAndWhatIsExpected) {
  SimulatedISURSuturingRobot joints("isur");
  joints.setProperty("initial_joints", std::vector<double>(8, 0.1));
  core::Result r = joints.configure();
  EXPECT_FALSE(r);
  EXPECT_EQ(r.message,
            "component 'isur': property initial_joints has 8 values; the I-SUR suturing has 14 joints: give one "
            "position per joint (rad, m for prismatic joints)");

  SimulatedISURSuturingRobot sensor("isur");
  sensor.setProperty("left_sensor", std::string("nano99"));
  r = sensor.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property left_sensor is 'nano99'; expected atiNano17, atiNano43 or ftSens");

  SimulatedISURSuturingRobot time("isur");
  time.setProperty("actuation_time", 0.0);
  r = time.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property actuation_time is 0.000000 s; expected > 0 s");

  SimulatedISURSuturingRobot event("isur");
  event.setProperty("actuate_event", std::string());
  r = event.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property actuate_event is ''; expected an event name of 1 to 63 characters");

  SimulatedISURSuturingRobot frame("isur");
  frame.setProperty("right_tool_frame", KDL::Frame(KDL::Rotation(1, 0, 0, 0, 2, 0, 0, 0, 1), KDL::Vector::Zero()));
  r = frame.configure();
  EXPECT_FALSE(r);
  EXPECT_CONTAINS(r.message, "property right_tool_frame must be a finite frame with an orthonormal rotation");
}

TEST(SimulatedISURSuturingRobot, IsRegisteredInTheCobraSimPackage) {
  deploy::PackageRegistry registry;
  addBuiltinPackages(registry);
  registry.load("cobra_sim");
  const std::unique_ptr<core::Component> robot = registry.create("SimulatedISURSuturingRobot", "isur");
  ASSERT_NE(robot, nullptr);
  EXPECT_EQ(robot->role(), core::Role::Bridge);
  EXPECT_NE(robot->findPort("desLeftCartPose"), nullptr);
}

}  // namespace
}  // namespace cobra::components::test
