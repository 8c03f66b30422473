// MujocoPuma260World and MujocoPuma260Arm on apps/puma260/world/puma260.xml: the MuJoCo tool tip
// against the closed-form Puma 260 kinematics, MuJoCo's gravity against the analytic arm's, the
// FTSens wrench against MuJoCo's contact forces and the surface's stiffness, the six drives closing
// their loops on MuJoCo, brakes, a compliant crossing of the surface, determinism, no allocation,
// and the one-line errors for bad model files.

#include "cobra/sim/mujoco_puma260.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "cobra/kinematics/puma260.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::Cia402State;
using cobra::sim::MujocoPuma260Arm;
using cobra::sim::MujocoPuma260World;
using cobra::sim::Puma260ArmModel;
namespace cw = cobra::sim::controlword;

const std::string kModel = std::string(COBRA_SOURCE_DIR) + "/apps/puma260/world/puma260.xml";
constexpr double kGravity = 9.81;  // m/s², the model's

std::array<double, 6> randomConfiguration(std::mt19937_64& rng) {
  const auto limits = cobra::kinematics::Puma260Solver::defaultLimits();
  std::array<double, 6> q{};
  for (std::size_t i = 0; i < 6; ++i) q[i] = std::uniform_real_distribution<double>(limits.lower[i], limits.upper[i])(rng);
  return q;
}

KDL::JntArray joints(const std::array<double, 6>& q) {
  KDL::JntArray j(6);
  for (unsigned i = 0; i < 6; ++i) j(i) = q[i];
  return j;
}

TEST(MujocoPuma260World, ToolTipAndFlangeAreTheClosedFormKinematicsWithTheToolTransform) {
  MujocoPuma260World world(kModel);
  // The tool the model declares: sensor frame 0.018 m beyond the flange, tool tip 0.10 m beyond it.
  EXPECT_TRUE(KDL::Equal(world.flangeToSensor(), KDL::Frame(KDL::Vector(0, 0, 0.018)), 1e-12));
  EXPECT_TRUE(KDL::Equal(world.sensorToTool(), KDL::Frame(KDL::Vector(0, 0, 0.10)), 1e-12));
  cobra::kinematics::Puma260Solver flange;
  cobra::kinematics::Puma260Solver tool({}, cobra::kinematics::Puma260Solver::defaultLimits(), KDL::Frame::Identity(),
                                        KDL::Frame(KDL::Vector(0, 0, 0.118)));
  std::mt19937_64 rng(260);
  for (int n = 0; n < 200; ++n) {  // 200 seeded random configurations within the joint limits
    const auto q = randomConfiguration(rng);
    world.setJointPositions(q);
    KDL::Frame expected_flange, expected_tool;
    ASSERT_EQ(flange.forward(joints(q), expected_flange), cobra::kinematics::IkStatus::Ok);
    ASSERT_EQ(tool.forward(joints(q), expected_tool), cobra::kinematics::IkStatus::Ok);
    EXPECT_TRUE(KDL::Equal(world.flangePose(), expected_flange, 1e-9)) << "configuration " << n;
    EXPECT_TRUE(KDL::Equal(world.toolPose(), expected_tool, 1e-9)) << "configuration " << n;
    for (int i = 0; i < 6; ++i) EXPECT_EQ(world.jointPosition(i), q[static_cast<std::size_t>(i)]);
  }
}

// The analytic arm (sim::Puma260Arm) lumps everything beyond the elbow on the forearm's axis; the
// model matches it exactly with the wrist straight (q5 = 0). Otherwise the masses beyond the wrist
// centre (link 6 0.05 kg at 0.045 m, FTSens 0.122 kg at 0.064 m, tool 0.05 kg at 0.134 m: 0.0168
// kg·m) swing off that axis: joints 2 and 3 differ by at most 2·g·0.0168 = 0.33 N·m.
TEST(MujocoPuma260World, GravityAtRestIsTheAnalyticArmsToTheOrderOfTheWristMasses) {
  MujocoPuma260World world(kModel);
  const cobra::sim::Puma260Arm analytic(Puma260ArmModel::defaults());
  const double wrist_bound = 2.0 * kGravity * (0.05 * 0.045 + 0.122 * 0.06437 + 0.05 * 0.13337);
  std::mt19937_64 rng(13);
  double worst_straight = 0.0, worst_bent = 0.0;
  for (int n = 0; n < 200; ++n) {  // 200 seeded random configurations, the first 100 with q5 = 0
    auto q = randomConfiguration(rng);
    if (n < 100) q[4] = 0.0;
    world.setJointPositions(q);
    const auto tau = analytic.gravityTorque(q);
    EXPECT_NEAR(world.biasTorque(0), 0.0, 1e-9);  // vertical axis
    for (int i : {1, 2}) {
      const double difference = std::abs(world.biasTorque(i) - tau[static_cast<std::size_t>(i)]);
      (n < 100 ? worst_straight : worst_bent) = std::max(n < 100 ? worst_straight : worst_bent, difference);
    }
  }
  EXPECT_LT(worst_straight, 1e-5);  // N·m: the forearm's centre of mass is rounded to 1 µm
  EXPECT_LT(worst_bent, wrist_bound);
  EXPECT_GT(worst_bent, 0.01);  // the wrist masses do show: the bound is not vacuous
}

/// The six drives enabled in cyclic synchronous position, holding `target`.
void enable(MujocoPuma260Arm& arm, const std::array<double, 6>& target) {
  for (std::uint16_t word : {cw::kShutdown, cw::kSwitchOnCommand, cw::kEnableOperationCommand}) {
    for (int i = 0; i < 6; ++i) {
      arm.drive(i).setControlword(word);
      arm.drive(i).setTargetPosition(target[static_cast<std::size_t>(i)]);
    }
    arm.step(1e-3);
    arm.step(1e-3);
  }
  for (int i = 0; i < 6; ++i) ASSERT_EQ(arm.drive(i).state(), Cia402State::OperationEnabled) << "drive " << i;
}

/// Joint angles (closed form) with the tool tip at `tip`, pointing straight down, on the branch of
/// `seed` (default: elbow up over the surface).
std::array<double, 6> toolDownAt(const KDL::Vector& tip, std::array<double, 6> seed = {0, 1.2, -2.4, 0, -0.4, 0}) {
  static cobra::kinematics::Puma260Solver solver({}, cobra::kinematics::Puma260Solver::defaultLimits(),
                                                 KDL::Frame::Identity(), KDL::Frame(KDL::Vector(0, 0, 0.118)));
  const KDL::JntArray from = joints(seed);
  KDL::JntArray q(6);
  EXPECT_EQ(solver.inverse(KDL::Frame(KDL::Rotation::RotX(M_PI), tip), from, q), cobra::kinematics::IkStatus::Ok);
  return {q(0), q(1), q(2), q(3), q(4), q(5)};
}

// Static press: the drives hold the tool tip 0.2 mm, then 0.6 mm below the top of the surface. In
// equilibrium the tool body carries the contact force and its weight, so the wrench the tool exerts
// on the sensor is their sum (and their moment about the sensor frame's origin), expressed in the
// sensor frame. The surface's stiffness is the slope force / depth between the two presses.
TEST(MujocoPuma260World, ThePressedToolReadsTheContactForceAndItsWeightInTheSensorFrame) {
  const KDL::Vector top(0.35, 0.0, 0.115);
  auto from = toolDownAt(top + KDL::Vector(0, 0, 0.01));
  MujocoPuma260Arm arm(kModel, MujocoPuma260Arm::defaultDrives(), from);
  enable(arm, from);
  std::array<double, 2> pressed{}, depth{};
  for (std::size_t press = 0; press < 2; ++press) {
    const auto q = toolDownAt(top - KDL::Vector(0, 0, press == 0 ? 0.0002 : 0.0006));
    double lowest = 1e9, highest = 0.0;
    for (int k = 0; k < 3000; ++k) {  // 1 s ramp (10 mm/s at the first contact), 2 s to settle
      const double s = std::min(1.0, k / 1000.0);
      for (int i = 0; i < 6; ++i) {
        const auto j = static_cast<std::size_t>(i);
        arm.drive(i).setTargetPosition(from[j] + s * (q[j] - from[j]));
      }
      arm.step(1e-3);
      if (k >= 2900) {
        lowest = std::min(lowest, arm.world().contactForce());
        highest = std::max(highest, arm.world().contactForce());
      }
    }
    for (int i = 0; i < 6; ++i) ASSERT_EQ(arm.drive(i).state(), Cia402State::OperationEnabled) << "drive " << i;
    EXPECT_LT(highest - lowest, 0.05 * highest) << "press " << press << ": steady, not a limit cycle";
    pressed[press] = arm.world().contactForce();
    depth[press] = arm.world().penetration();
    from = q;
  }
  const double stiffness = (pressed[1] - pressed[0]) / (depth[1] - depth[0]);
  RecordProperty("contact_stiffness_N_per_m", std::to_string(stiffness));
  std::printf("static press: %.3f N at %.6f m, %.3f N at %.6f m: stiffness %.0f N/m\n", pressed[0], depth[0], pressed[1],
              depth[1], stiffness);
  EXPECT_GT(stiffness, 1e4);
  EXPECT_LT(stiffness, 1e5);
  MujocoPuma260World& world = arm.world();
  ASSERT_GT(world.contactForce(), 5.0);
  // The contact forces on the tool and their moment about the sensor frame, from MuJoCo's contacts.
  const mjModel* m = world.model();
  const mjData* d = world.data();
  const KDL::Frame sensor = world.sensorPose();
  KDL::Vector force = KDL::Vector::Zero(), moment = KDL::Vector::Zero();
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    mjtNum local[6];
    mj_contactForce(m, d, i, local);
    const KDL::Vector normal(c.frame[0], c.frame[1], c.frame[2]), t1(c.frame[3], c.frame[4], c.frame[5]),
        t2(c.frame[6], c.frame[7], c.frame[8]);
    // MuJoCo: the force on geom2 (the surface in the model's pairs); the tool gets the opposite.
    const KDL::Vector on_tool = -(local[0] * normal + local[1] * t1 + local[2] * t2);
    force += on_tool;
    moment += (KDL::Vector(c.pos[0], c.pos[1], c.pos[2]) - sensor.p) * on_tool;
  }
  const double tool_mass = world.toolMass();
  EXPECT_NEAR(tool_mass, 0.05, 1e-12);
  const KDL::Vector weight(0, 0, -tool_mass * kGravity);
  const KDL::Vector tool_com = sensor * KDL::Vector(0, 0, 0.06);  // the tool's centre of mass (model)
  const KDL::Wrench expected_base(force + weight, moment + (tool_com - sensor.p) * weight);
  const KDL::Wrench expected = sensor.M.Inverse() * expected_base;  // sensor axes
  const KDL::Wrench measured = world.sensorWrench();
  // The residual dynamics of a settled arm: 1 % of the contact force.
  const double tolerance = 0.01 * world.contactForce();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(measured.force(i), expected.force(i), tolerance) << "force axis " << i;
    EXPECT_NEAR(measured.torque(i), expected.torque(i), tolerance * 0.1) << "torque axis " << i;
  }
  // The tool points down: pushed up by the surface, the sensor feels -z of its frame pushed in
  // with about the contact force.
  EXPECT_LT(measured.force.z(), -0.9 * world.contactForce());
  EXPECT_NEAR(world.contactForce(), force.Norm(), 0.2 * force.Norm());  // friction is the rest
  EXPECT_NEAR(world.penetration(), 0.0006, 0.0002);
  EXPECT_EQ(world.warningCount(), 0);
}

TEST(MujocoPuma260World, OffTheSurfaceNothingTouches) {
  MujocoPuma260World world(kModel);
  world.setJointPositions(toolDownAt(KDL::Vector(0.35, -0.12, 0.10)));
  EXPECT_EQ(world.contactForce(), 0.0);
  EXPECT_EQ(world.penetration(), 0.0);
  const auto& s = world.surface();
  EXPECT_TRUE(KDL::Equal(s.centre, KDL::Vector(0.35, 0.0, 0.035), 1e-12));
  EXPECT_TRUE(KDL::Equal(s.axis, KDL::Vector(1, 0, 0), 1e-12));
  EXPECT_DOUBLE_EQ(s.radius, 0.08);
  EXPECT_DOUBLE_EQ(s.half_length, 0.05);
  EXPECT_DOUBLE_EQ(world.toolBallRadius(), 0.005);
}

TEST(MujocoPuma260Arm, TheDrivesMoveTheMujocoArmToTheirTargets) {
  const auto start = toolDownAt(KDL::Vector(0.35, -0.12, 0.15));
  MujocoPuma260Arm arm(kModel, MujocoPuma260Arm::defaultDrives(), start);
  enable(arm, start);
  auto target = start;
  for (double& x : target) x += 0.1;
  for (int k = 0; k < 1500; ++k) {  // a 0.5 s ramp (a step would trip the following error), then hold
    const double s = std::min(1.0, k / 500.0);
    for (int i = 0; i < 6; ++i) {
      const auto j = static_cast<std::size_t>(i);
      arm.drive(i).setTargetPosition(start[j] + s * (target[j] - start[j]));
    }
    arm.step(1e-3);
  }
  for (int i = 0; i < 6; ++i) {
    // MuJoCo integrated the joint: the drive reports what MuJoCo has.
    EXPECT_EQ(arm.drive(i).position(), arm.world().jointPosition(i)) << "joint " << i + 1;
    EXPECT_NEAR(arm.world().jointPosition(i), target[static_cast<std::size_t>(i)], 1e-4) << "joint " << i + 1;
    EXPECT_TRUE(arm.drive(i).statusword() & cobra::sim::statusword::kTargetReached) << "joint " << i + 1;
  }
}

TEST(MujocoPuma260Arm, BrakesHoldTheUnpoweredArmAgainstGravity) {
  const std::array<double, 6> stretched = {0.0, 0.2, -1.3, 0.4, 0.6, 0.0};  // gravity loads joints 2, 3, 5
  MujocoPuma260Arm arm(kModel, MujocoPuma260Arm::defaultDrives(), stretched);
  for (int k = 0; k < 5000; ++k) arm.step(1e-3);  // 5 s, drives off (Switch on disabled)
  ASSERT_EQ(arm.drive(1).state(), Cia402State::SwitchOnDisabled);
  ASSERT_GT(std::abs(arm.world().biasTorque(1)), 2.0);  // N·m the brake holds
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(arm.world().jointPosition(i), stretched[static_cast<std::size_t>(i)], 1e-4) << "joint " << i + 1;
  }
}

TEST(MujocoPuma260Arm, AFaultedDriveLetsItsJointGoToTheBrake) {
  const auto start = toolDownAt(KDL::Vector(0.35, -0.12, 0.15));
  MujocoPuma260Arm arm(kModel, MujocoPuma260Arm::defaultDrives(), start);
  enable(arm, start);
  arm.drive(1).injectFault(cobra::sim::error_code::kOverCurrent);
  for (int k = 0; k < 1000; ++k) arm.step(1e-3);
  EXPECT_EQ(arm.drive(1).state(), Cia402State::Fault);
  EXPECT_EQ(arm.drive(1).torque(), 0.0);
  EXPECT_NEAR(arm.world().jointPosition(1), start[1], 1e-3);  // held by the brake, not fallen
}

TEST(MujocoPuma260Arm, StepsAreDeterministicAndAllocateNothing) {
  const auto start = toolDownAt(KDL::Vector(0.35, -0.12, 0.10));
  const auto end = toolDownAt(KDL::Vector(0.35, 0.12, 0.10));  // across the surface
  const auto run = [&](MujocoPuma260Arm& arm) {
    enable(arm, start);
    for (int k = 0; k < 2000; ++k) {
      const double s = std::min(1.0, k / 1500.0);
      for (int i = 0; i < 6; ++i) {
        const auto j = static_cast<std::size_t>(i);
        arm.drive(i).setTargetPosition(start[j] + s * (end[j] - start[j]));
      }
      arm.step(1e-3);
    }
  };
  MujocoPuma260Arm a(kModel, MujocoPuma260Arm::defaultDrives(), start), b(kModel, MujocoPuma260Arm::defaultDrives(), start);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { run(a); }), 0);
  run(b);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(a.world().jointPosition(i), b.world().jointPosition(i));
  EXPECT_EQ(a.world().warningCount(), 0);
  EXPECT_EQ(a.world().sensorWrench(), b.world().sensorWrench());
}

// The world is fit for the §6.3 loop: the tool crosses the surface on the nominal path (tool down,
// (0.35, -0.12, 0.10) to (0.35, 0.12, 0.10) m in 8 s) under a minimal vertical admittance written
// here (M = 2 kg, D = 300 N·s/m, K = 100 N/m on the measured sensor force, base z, tool weight
// removed; 1 kHz, no sensor or bus delay): it rides over the top (15 mm above the path) with a
// bounded contact force and penetration, no drive fault and no MuJoCo warning. Measured: 13.1 N,
// 0.92 mm at the most.
TEST(MujocoPuma260Arm, ACompliantToolRidesOverTheSurfaceWithoutFault) {
  std::array<double, 6> seed = toolDownAt(KDL::Vector(0.35, -0.12, 0.10));
  const auto ik = [&](double y, double z) { return seed = toolDownAt(KDL::Vector(0.35, y, z), seed); };
  const auto start = ik(-0.12, 0.10);
  MujocoPuma260Arm arm(kModel, MujocoPuma260Arm::defaultDrives(), start);
  enable(arm, start);
  constexpr double kMass = 2.0, kDamping = 300.0, kStiffness = 100.0;  // kg, N·s/m, N/m
  double dz = 0.0, vz = 0.0, highest_force = 0.0, deepest = 0.0, top = 0.0;
  for (int k = 0; k < 8000; ++k) {
    const double y = -0.12 + 0.24 * k / 8000.0;
    const KDL::Vector f = arm.world().sensorPose().M * arm.world().sensorWrench().force;  // base axes
    const double environment = f.z() + arm.world().toolMass() * kGravity;  // N, up
    vz += (environment - kDamping * vz - kStiffness * dz) / kMass * 1e-3;
    dz += vz * 1e-3;
    const auto target = ik(y, 0.10 + dz);
    for (int i = 0; i < 6; ++i) arm.drive(i).setTargetPosition(target[static_cast<std::size_t>(i)]);
    arm.step(1e-3);
    highest_force = std::max(highest_force, arm.world().contactForce());
    deepest = std::max(deepest, arm.world().penetration());
    top = std::max(top, arm.world().toolPose().p.z());
  }
  for (int i = 0; i < 6; ++i) EXPECT_EQ(arm.drive(i).state(), Cia402State::OperationEnabled) << "drive " << i;
  EXPECT_GT(highest_force, 1.0);  // it did touch
  EXPECT_LT(highest_force, 20.0);
  EXPECT_LT(deepest, 0.0015);
  EXPECT_GT(top, 0.114);  // over the top of the surface (0.115 m)
  EXPECT_EQ(arm.world().contactForce(), 0.0);  // past it
  EXPECT_EQ(arm.world().warningCount(), 0);
}

// ---- Bad model files: one line naming the file and what was expected.

std::string referenceModel() {
  std::ifstream in(kModel);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The reference model with `from` replaced by `to`, written to a temporary file.
std::string variant(const std::string& name, const std::string& from, const std::string& to) {
  std::string text = referenceModel();
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const std::string path = ::cobra::test_support::scratchPath(name).string();
  std::ofstream(path) << text;
  return path;
}

std::string loadError(const std::string& path) {
  return cobra::test_support::messageOf([&] { MujocoPuma260World world(path); });
}

TEST(MujocoPuma260World, AMissingOrMalformedFileIsMujocosErrorWithTheFile) {
  const std::string missing = ::cobra::test_support::scratchPath("no_such_world.xml").string();
  const std::string message = loadError(missing);
  EXPECT_CONTAINS(message, missing + ": cannot load the MuJoCo model: XML parse error");
  EXPECT_CONTAINS(message, "FILE_NOT_FOUND");
  EXPECT_EQ(message.find('\n'), std::string::npos);
  const std::string malformed = ::cobra::test_support::scratchPath("malformed_world.xml").string();
  std::ofstream(malformed) << "<mujoco>\n  <worldbody>\n    <body>\n</mujoco>\n";
  EXPECT_CONTAINS(loadError(malformed), malformed + ": cannot load the MuJoCo model: XML parse error");
  EXPECT_CONTAINS(loadError(malformed), "MISMATCHED_ELEMENT");
}

TEST(MujocoPuma260World, AModelWithoutSixMotorsSaysHowManyItHas) {
  const std::string path = variant("five_motors.xml", "<motor name=\"motor6\" joint=\"joint6\"/>", "");
  EXPECT_EQ(loadError(path), path + ": has 5 actuators; the Puma 260 world needs 6 motor actuators, one per joint");
}

TEST(MujocoPuma260World, AModelWithoutTheSensorSiteNamesIt) {
  std::string path = variant("no_site.xml", "<site name=\"ftsens\" pos=\"0 0 0\" size=\"0.005\"/>", "");
  // The sensors need the site too: drop them in the same file.
  std::string text = referenceModel();
  text.replace(text.find("<site name=\"ftsens\" pos=\"0 0 0\" size=\"0.005\"/>"), 47, "");
  const auto begin = text.find("<sensor>"), end = text.find("</sensor>") + 9;
  text.replace(begin, end - begin, "");
  std::ofstream(path) << text;
  EXPECT_EQ(loadError(path), path + ": no site 'ftsens' (the FTSens sensor frame, on the tool body); the Puma 260 "
                                    "world needs it");
}

TEST(MujocoPuma260World, ASurfaceBeyondTheReachSaysTheDistanceAndTheReach) {
  const std::string path = variant("far_surface.xml", "pos=\"0.35 0 0.035\"", "pos=\"1.5 0 0.035\"");
  EXPECT_EQ(loadError(path), path + ": the surface is 1.47 m from the shoulder, beyond the arm's reach of 0.616 m "
                                    "(geom 'surface' centred at (1.5, 0, 0.035) m)");
}

}  // namespace
