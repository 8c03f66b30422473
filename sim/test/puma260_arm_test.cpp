// Puma260Arm: the gravity torques cross-checked against the potential energy computed from the
// Puma 260 forward kinematics (kinematics/puma260.hpp) by central differences; brakes hold an
// unpowered arm; parameter errors name the joint.

#include "cobra/sim/puma260_arm.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cobra/kinematics/puma260.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::Puma260Arm;
using cobra::sim::Puma260ArmModel;

// Model with the forearm's mass at the wrist centre (r3 = d4) and no upper-arm mass: V = m·g·z of
// the wrist centre, whose height the closed-form kinematics gives (flange minus d6 along its z).
TEST(Puma260Arm, GravityIsTheGradientOfThePotentialFromTheKinematics) {
  Puma260ArmModel model = Puma260ArmModel::defaults();
  const cobra::kinematics::Puma260Parameters p;
  model.upper_arm_mass = 0.0;
  model.forearm_mass = 1.7;
  model.forearm_com = p.d4;
  const Puma260Arm arm(model);
  cobra::kinematics::Puma260Solver solver;
  const auto wrist_height = [&](const std::array<double, 6>& q) {
    KDL::JntArray joints(6);
    for (unsigned i = 0; i < 6; ++i) joints(i) = q[i];
    KDL::Frame flange;
    EXPECT_EQ(solver.forward(joints, flange), cobra::kinematics::IkStatus::Ok);
    return (flange.p - flange.M.UnitZ() * p.d6).z();
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-2.0, 2.0);
  for (int n = 0; n < 200; ++n) {  // 200 random configurations
    std::array<double, 6> q{};
    for (double& x : q) x = angle(rng);
    const auto tau = arm.gravityTorque(q);
    for (std::size_t i = 0; i < 6; ++i) {
      auto plus = q, minus = q;
      plus[i] += 1e-6;
      minus[i] -= 1e-6;
      const double dv = model.forearm_mass * model.gravity * (wrist_height(plus) - wrist_height(minus)) / 2e-6;
      EXPECT_NEAR(tau[i], dv, 1e-5) << "joint " << i + 1;
    }
  }
}

TEST(Puma260Arm, BrakesHoldAnUnpoweredArmAndGravityPullsAnEnabledOneWithoutTorque) {
  Puma260Arm arm(Puma260ArmModel::defaults(), {0, 0, 0, 0, 0, 0});
  for (int i = 0; i < 500; ++i) arm.step(1e-3);  // never enabled: brakes
  EXPECT_EQ(arm.drive(1).position(), 0.0);
  // Enable joint 2 in cyclic torque mode with zero torque: gravity pulls the horizontal upper arm down.
  cobra::sim::Cia402Drive& shoulder = arm.drive(1);
  shoulder.setModeOfOperation(cobra::sim::Cia402Mode::CyclicSynchronousTorque);
  shoulder.setTargetTorque(0.0);
  for (int word : {0x06, 0x07, 0x0F}) {
    shoulder.setControlword(static_cast<std::uint16_t>(word));
    arm.step(1e-3);
  }
  ASSERT_EQ(shoulder.state(), cobra::sim::Cia402State::OperationEnabled);
  for (int i = 0; i < 100; ++i) arm.step(1e-3);
  EXPECT_LT(shoulder.position(), -0.01);
  // Switched off: the brake (20 N·m on 0.08 kg·m²) stops the falling arm within 50 ms and holds it.
  shoulder.setControlword(0x00);
  for (int i = 0; i < 50; ++i) arm.step(1e-3);
  EXPECT_LT(std::abs(shoulder.velocity()), 1e-6);
  const double held = shoulder.position();
  for (int i = 0; i < 500; ++i) arm.step(1e-3);
  EXPECT_NEAR(shoulder.position(), held, 1e-6);
}

TEST(Puma260Arm, BadParametersNameTheJoint) {
  Puma260ArmModel model = Puma260ArmModel::defaults();
  model.drives[3].inertia = 0.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { Puma260Arm arm(model); }),
                  "Puma 260 arm: joint 4: CiA 402 drive: inertia = 0.000000, expected > 0.000000 kg*m^2");
  model = Puma260ArmModel::defaults();
  model.forearm_mass = -1.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { Puma260Arm arm(model); }),
                  "forearm_mass = -1.000000, expected >= 0");
}

}  // namespace
