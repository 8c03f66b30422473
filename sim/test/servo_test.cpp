// ServoRobot and CartesianServo: the exact first-order response, limits, encoder quantisation,
// a UR5 driven along a Cartesian line with the lag's predictable error, IK failure holding the
// last command, the continuity rule (a jump, a wrist branch change refused and held; continuing
// from a joint command), determinism, no allocation in step, parameter errors.

#include "cobra/sim/servo.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cobra/kinematics/ur5.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::kinematics::JointLimits;
using cobra::kinematics::JointType;
using cobra::sim::ServoRobot;
using cobra::sim::ServoRobotModel;
using cobra::test_support::messageOf;

JointLimits twoJoints() {
  JointLimits l;
  l.types = {JointType::Revolute, JointType::Prismatic};
  l.lower = {-1.0, 0.0};
  l.upper = {1.0, 0.2};
  return l;
}

TEST(ServoRobot, FollowsAHeldCommandExactlyAsAFirstOrderLag) {
  ServoRobot robot(cobra::sim::uniformServoModel("two", twoJoints(), 0.05, 100.0, 0.0), std::vector{0.0, 0.0});
  ASSERT_TRUE(robot.command(std::vector{0.5, 0.1}));
  for (int i = 0; i < 30; ++i) EXPECT_TRUE(robot.step(1e-3).ok());
  EXPECT_NEAR(robot.position()(0), 0.5 * (1 - std::exp(-0.03 / 0.05)), 1e-12);
  EXPECT_NEAR(robot.position()(1), 0.1 * (1 - std::exp(-0.03 / 0.05)), 1e-12);
}

TEST(ServoRobot, ClampsAndFlagsPositionAndVelocityLimits) {
  ServoRobot robot(cobra::sim::uniformServoModel("two", twoJoints(), 0.01, 0.5, 0.0), std::vector{0.0, 0.0});
  ASSERT_TRUE(robot.command(std::vector{2.0, 0.1}));
  const auto status = robot.step(1e-3);
  EXPECT_EQ(status.position_limited, 0b01U);
  EXPECT_EQ(status.velocity_limited, 0b11U);
  EXPECT_DOUBLE_EQ(robot.commanded()(0), 1.0);
  EXPECT_DOUBLE_EQ(robot.velocity()(0), 0.5);
  EXPECT_EQ(robot.step(1e-3).position_limited, 0U);
  for (int i = 0; i < 5000; ++i) robot.step(1e-3);
  EXPECT_NEAR(robot.position()(0), 1.0, 1e-9);
  EXPECT_FALSE(robot.command(std::vector{0.0}));
  EXPECT_FALSE(robot.command(std::vector{std::nan(""), 0.0}));
}

TEST(ServoRobot, EncoderQuantisesToCountsPerRevolutionAndPerMetre) {
  ServoRobot robot(cobra::sim::uniformServoModel("two", twoJoints(), 0.01, 10.0, 1000.0), std::vector{0.0, 0.0});
  robot.command(std::vector{0.01, 0.0123});
  for (int i = 0; i < 1000; ++i) robot.step(1e-3);
  const double rad_step = 2 * std::numbers::pi / 1000.0;
  EXPECT_DOUBLE_EQ(robot.measured()(0), rad_step * std::round(robot.position()(0) / rad_step));
  EXPECT_DOUBLE_EQ(robot.measured()(1), 0.012);
  EXPECT_LE(std::abs(robot.measured()(0) - robot.position()(0)), rad_step / 2);
}

TEST(CartesianServo, Ur5AlongALineLagsByVelocityTimesTimeConstant) {
  cobra::kinematics::Ur5Solver solver;
  const std::vector<double> q0{0.3, -1.2, 1.5, -1.9, -1.57, 0.2};
  constexpr double kTau = 0.02;  // s
  ServoRobot robot(cobra::sim::uniformServoModel("UR5", solver.limits(), kTau, std::numbers::pi, 0.0), q0);
  cobra::sim::CartesianServo servo(solver, robot);
  KDL::Frame start;
  ASSERT_TRUE(servo.pose(start));
  constexpr double kSpeed = 0.05;  // m/s along x of the base
  constexpr double kDt = 1e-3;
  double worst_lagged = 0.0, worst_delayed = 0.0, lag_at_end = 0.0;
  for (int i = 1; i <= 2000; ++i) {
    const double t = i * kDt;
    KDL::Frame target = start;
    target.p += KDL::Vector(kSpeed * t, 0, 0);
    ASSERT_EQ(servo.command(target).ik, cobra::kinematics::IkStatus::Ok);
    ASSERT_TRUE(robot.step(kDt).ok());
    KDL::Frame actual;
    ASSERT_TRUE(servo.pose(actual));
    if (t > 10 * kTau) {
      KDL::Frame delayed = start;
      delayed.p += KDL::Vector(kSpeed * (t - kTau), 0, 0);  // a first-order lag tracks a ramp τ behind
      worst_lagged = std::max(worst_lagged, (actual.p - target.p).Norm());
      worst_delayed = std::max(worst_delayed, (actual.p - delayed.p).Norm());
      lag_at_end = (actual.p - target.p).Norm();
    }
  }
  EXPECT_NEAR(lag_at_end, kSpeed * kTau, 0.1 * kSpeed * kTau);
  EXPECT_LE(worst_lagged, 1.1 * kSpeed * kTau);
  EXPECT_LE(worst_delayed, 0.1 * kSpeed * kTau);
}

TEST(CartesianServo, HoldsTheLastValidCommandWhenIkFails) {
  cobra::kinematics::Ur5Solver solver;
  const std::vector<double> q0{0.3, -1.2, 1.5, -1.9, -1.57, 0.2};
  ServoRobot robot(cobra::sim::uniformServoModel("UR5", solver.limits(), 0.02, 3.0, 0.0), q0);
  cobra::sim::CartesianServo servo(solver, robot);
  KDL::Frame far(KDL::Vector(5.0, 0, 0));
  const auto status = servo.command(far);
  EXPECT_TRUE(status.holding);
  EXPECT_EQ(status.ik, cobra::kinematics::IkStatus::Unreachable);
  for (unsigned j = 0; j < 6; ++j) EXPECT_DOUBLE_EQ(robot.commanded()(j), q0[j]);
}

TEST(CartesianServo, RefusesAJumpBeyondMaxVelocityTimesDtAndHolds) {
  cobra::kinematics::Ur5Solver solver;
  const std::vector<double> q0{0.3, -1.2, 1.5, -1.9, -1.57, 0.2};
  ServoRobot robot(cobra::sim::uniformServoModel("UR5", solver.limits(), 0.02, 3.0, 0.0), q0);
  cobra::sim::CartesianServo servo(solver, robot, 0.002);  // 6 mrad per joint and period
  KDL::Frame start;
  ASSERT_TRUE(servo.pose(start));
  KDL::Frame jump = start;
  jump.p += KDL::Vector(0.0, 0.0, 0.05);  // 5 cm in one period
  const auto status = servo.command(jump);
  EXPECT_TRUE(status.holding);
  EXPECT_EQ(status.ik, cobra::kinematics::IkStatus::Discontinuous);
  EXPECT_GE(servo.lastRefusal().joint, 0);
  EXPECT_DOUBLE_EQ(servo.lastRefusal().allowed, 0.006);
  for (unsigned j = 0; j < 6; ++j) EXPECT_DOUBLE_EQ(robot.commanded()(j), q0[j]);
  // The same jump over 0.5 s is a legal command.
  EXPECT_FALSE(servo.command(jump, 0.5).holding);
}

TEST(CartesianServo, RefusesAWristBranchChangeAndTheRobotDoesNotSwing) {
  // q5 = 0.01 -> a pose whose nearest joints have q5 = -0.01: on the current wrist branch it needs
  // q4 and q6 turned by π. Refused; the robot holds still.
  cobra::kinematics::Ur5Solver solver;
  const std::vector<double> q0{0.1, -1.3, 1.5, -1.7, 0.01, 0.3};
  ServoRobot robot(cobra::sim::uniformServoModel("UR5", solver.limits(), 0.02, 3.14, 0.0), q0);
  cobra::sim::CartesianServo servo(solver, robot, 0.002);
  KDL::JntArray across(6);
  for (unsigned j = 0; j < 6; ++j) across(j) = q0[j];
  across(4) = -0.01;
  KDL::Frame target;
  ASSERT_EQ(solver.forward(across, target), cobra::kinematics::IkStatus::Ok);
  for (int i = 0; i < 100; ++i) {
    const auto status = servo.command(target);
    EXPECT_TRUE(status.holding);
    EXPECT_EQ(status.ik, cobra::kinematics::IkStatus::Discontinuous);
    robot.step(0.002);
  }
  for (unsigned j = 0; j < 6; ++j) EXPECT_NEAR(robot.position()(j), q0[j], 1e-12) << "joint " << j + 1;
}

TEST(CartesianServo, ContinuesFromTheLastJointCommand) {
  // A joint command moves the set point; the next Cartesian command is judged from there.
  cobra::kinematics::Ur5Solver solver;
  const std::vector<double> q0{0.3, -1.2, 1.5, -1.9, -1.57, 0.2};
  ServoRobot robot(cobra::sim::uniformServoModel("UR5", solver.limits(), 0.02, 3.0, 0.0), q0);
  cobra::sim::CartesianServo servo(solver, robot, 0.002);
  std::vector<double> q1 = q0;
  q1[0] += 0.8;
  ASSERT_TRUE(robot.command(q1));
  KDL::JntArray near(6);
  for (unsigned j = 0; j < 6; ++j) near(j) = q1[j];
  near(0) += 0.001;
  KDL::Frame target;
  ASSERT_EQ(solver.forward(near, target), cobra::kinematics::IkStatus::Ok);
  const auto status = servo.command(target);
  EXPECT_FALSE(status.holding);
  EXPECT_NEAR(robot.commanded()(0), q1[0] + 0.001, 1e-9);
}

TEST(ServoRobot, StepAndCartesianCommandAllocateNothing) {
  cobra::kinematics::Ur5Solver solver;
  const std::vector<double> q0{0.3, -1.2, 1.5, -1.9, -1.57, 0.2};
  ServoRobot robot(cobra::sim::uniformServoModel("UR5", solver.limits(), 0.02, 3.0, 4096.0), q0);
  cobra::sim::CartesianServo servo(solver, robot);
  KDL::Frame start;
  ASSERT_TRUE(servo.pose(start));
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 500; ++i) {
                KDL::Frame target = start;
                target.p += KDL::Vector(1e-5 * i, 0, 0);
                servo.command(target);
                robot.step(1e-3);
              }
            }),
            0);
}

TEST(ServoRobot, BadParametersAreNamed) {
  ServoRobotModel m = cobra::sim::uniformServoModel("arm", twoJoints(), 0.05, 1.0, 0.0);
  m.time_constant[1] = 0.0;
  EXPECT_CONTAINS(messageOf([&] { ServoRobot r(m, std::vector{0.0, 0.0}); }),
                  "servo robot 'arm': time_constant of joint 2 = 0.000000, expected a finite value > 0 s");
  m = cobra::sim::uniformServoModel("arm", twoJoints(), 0.05, 1.0, 0.0);
  m.max_velocity.pop_back();
  EXPECT_CONTAINS(messageOf([&] { ServoRobot r(m, std::vector{0.0, 0.0}); }), "max_velocity has 1 values, expected one per joint (2)");
  m = cobra::sim::uniformServoModel("arm", twoJoints(), 0.05, 1.0, 0.0);
  EXPECT_CONTAINS(messageOf([&] { ServoRobot r(m, std::vector{0.0}); }), "initial position has 1 values, expected 2");
}

}  // namespace
