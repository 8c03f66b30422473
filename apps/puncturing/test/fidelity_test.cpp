// The fidelity measures of a procedure (run/fidelity.hpp): tracking error and the joint-jump
// check of TrackingMonitor on made-up samples, ClearanceMonitor on the puncturing planning scene
// with the two robots' models, the allowed contacts measured apart.

#include "cobra/puncturing/fidelity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::puncturing {
namespace {

constexpr double kPi = 3.14159265358979323846;
const std::filesystem::path kScene = std::filesystem::path(COBRA_SOURCE_DIR) / "planning" / "scenes" / "puncturing.scene";

KDL::JntArray joints(std::initializer_list<double> values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  unsigned i = 0;
  for (double v : values) q(i++) = v;
  return q;
}

TEST(TrackingMonitor, MeasuresPositionInMillimetresAndOrientationInDegreesOverTheSamplesThatCount) {
  TrackingMonitor m("I-SUR needle", {}, 0.001);
  const KDL::Frame commanded(KDL::Rotation::RotX(0.3), KDL::Vector(0.1, 0.2, 0.3));
  // 3 mm and 2 deg off while counting, then 50 mm and 10 deg off while not (teleoperation).
  for (int i = 0; i < 100; ++i)
    m.step(0.001 * i, true, "root.Moving", commanded,
           KDL::Frame(commanded.M * KDL::Rotation::RotY(2.0 * kPi / 180.0), commanded.p + KDL::Vector(0, 0.003, 0)),
           nullptr);
  for (int i = 100; i < 200; ++i)
    m.step(0.001 * i, false, "root.Teleoperation", commanded,
           KDL::Frame(commanded.M * KDL::Rotation::RotZ(10.0 * kPi / 180.0), commanded.p + KDL::Vector(0.05, 0, 0)),
           nullptr);
  const TrackingFigures& f = m.figures();
  EXPECT_NEAR(f.position_mm.value, 3.0, 1e-9);
  EXPECT_NEAR(f.orientation_deg.value, 2.0, 1e-9);
  EXPECT_EQ(f.position_mm.state, "root.Moving");
  EXPECT_NEAR(f.seconds_sampled, 0.1, 1e-9);
  EXPECT_EQ(f.seconds_above_5mm, 0.0);
  // The plots' window sees every sample, counted or not.
  const auto [mm, deg] = m.takeWindowMaximum();
  EXPECT_NEAR(mm, 50.0, 1e-9);
  EXPECT_NEAR(deg, 10.0, 1e-9);
  EXPECT_TRUE(std::isnan(m.takeWindowMaximum().first));
}

TEST(TrackingMonitor, CountsTheTimeAboveFiveMillimetresAndKeepsWhenTheWorstHappened) {
  TrackingMonitor m("UR5 probe", {}, 0.001);
  const KDL::Frame commanded;
  for (int i = 0; i < 1000; ++i) {
    const double off = i >= 400 && i < 650 ? 0.006 + 1e-5 * (i == 500) : 0.001;
    m.step(0.001 * i, true, i == 500 ? "root.MoveToSkin.Approach.Moving" : "root.Idle", commanded,
           KDL::Frame(KDL::Vector(off, 0, 0)), nullptr);
  }
  EXPECT_NEAR(m.figures().seconds_above_5mm, 0.25, 1e-9);
  EXPECT_NEAR(m.figures().position_mm.value, 6.01, 1e-9);
  EXPECT_NEAR(m.figures().position_mm.at, 0.5, 1e-12);
  EXPECT_EQ(m.figures().position_mm.state, "root.MoveToSkin.Approach.Moving");
}

TEST(TrackingMonitor, AJointAtItsVelocityLimitIsAJumpEpisodeUntilItCalmsDown) {
  // Two joints, 1 rad/s and 0.1 m/s: 1 mrad and 0.1 mm per 1 ms step at the limit.
  TrackingMonitor m("robot", {1.0, 0.1}, 0.001);
  const KDL::Frame pose;
  double q0 = 0.0, q1 = 0.0;
  auto move = [&](int steps, double speed0, double speed1, bool counts = true) {
    for (int i = 0; i < steps; ++i) {
      q0 += speed0 * 0.001;
      q1 += speed1 * 0.001;
      const KDL::JntArray q = joints({q0, q1});
      m.step(0.0, counts, "root.Moving", pose, pose, &q);
    }
  };
  move(100, 0.9, 0.09);  // 90 % of the limits: a fast but followed motion
  EXPECT_EQ(m.figures().joint_jumps, 0);
  EXPECT_NEAR(m.figures().joint_speed.value, 0.9, 1e-6);
  move(50, 0.2, 0.1);   // joint 2 at its limit: one episode however long
  move(50, 0.2, 0.02);  // calm
  move(1, 5.0, 0.0);    // a jump beyond the limit: a second one
  move(20, 0.0, 0.0);
  move(30, 1.0, 0.0, false);  // not counted (teleoperation)
  EXPECT_EQ(m.figures().joint_jumps, 2);
  EXPECT_NEAR(m.figures().joint_speed.value, 5.0, 1e-6);
  EXPECT_CONTAINS(m.figures().joint_jump_log, "joint 2 at 100 % of its velocity limit (root.Moving)");
  EXPECT_CONTAINS(m.figures().joint_jump_log, "joint 1 at 500 %");
}

/// The puncturing planning scene as the deployment configures the planner: the needle frame has
/// z along the needle, the I-SUR model's needle is its tool's x axis.
planning::SceneDescription scene() {
  planning::SceneDescription s = planning::loadScene(kScene);
  s.robots[s.robotIndex("isur")].tool_in_model_tool = KDL::Frame(KDL::Rotation::RotY(kPi / 2));
  return s;
}

const std::vector<AllowedContact> kContacts = {{"probe on skin", "us_probe", "phantom"},
                                               {"needle in tissue", "needle", "phantom"}};

// Configurations and their tool poses (base, FK, tool frames of world.lua): the I-SUR's initial
// one, and the UR5 elbow down (world.lua's initial configuration before issue 15).
const KDL::JntArray kUr5Joints = joints({0.798, -3.071, 1.714, -0.214, -1.571, -2.344});
const KDL::JntArray kIsurJoints = joints({0.021, 0.013, 0.224, 0, 0, 0.7, 0.7, 0});

KDL::Frame probePose(const KDL::JntArray& q) {
  kinematics::Ur5Solver solver;
  KDL::Frame flange;
  EXPECT_EQ(solver.forward(q, flange), kinematics::IkStatus::Ok);
  return KDL::Frame(KDL::Rotation::RotZ(kPi / 2), KDL::Vector(0.3, -0.5, 0)) * flange * KDL::Frame(KDL::Vector(0, 0, 0.12));
}

KDL::Frame needlePose(const KDL::JntArray& q) {
  kinematics::IsurPuncturingSolver solver;
  KDL::Frame tip;
  EXPECT_EQ(solver.forward(q, tip), kinematics::IkStatus::Ok);
  return KDL::Frame(KDL::Vector(0, -0.05, 1.0)) * tip * KDL::Frame(KDL::Rotation::RotY(kPi / 2));
}

TEST(ClearanceMonitor, TheNeedleInTheSkinIsAContactApartWhenAllowedAndTheClosestPairWhenNot) {
  ClearanceMonitor monitor(scene(), kContacts);
  EXPECT_DOUBLE_EQ(monitor.threshold(), 0.005);
  // The needle 10 deg from vertical, its tip 2 mm under the skin (phantom top z = 0.1 m); the probe
  // at its initial pose.
  const KDL::Frame needle(KDL::Rotation::RPY(kPi, 0.1708, kPi), KDL::Vector(0.0, 0.0, 0.098));
  const KDL::Frame probe = probePose(kUr5Joints);
  std::vector<KDL::JntArray> none(2);
  const ClearanceSample allowed = monitor.measure(needle, probe, {true, true}, none, true);
  ASSERT_FALSE(std::isnan(allowed.clearance));
  ASSERT_EQ(allowed.contacts.size(), 2u);
  EXPECT_EQ(allowed.contacts[1], 0.0) << "the needle is in the phantom";
  EXPECT_GT(allowed.clearance, 0.0);
  const ClearanceSample refused = monitor.measure(needle, probe, {true, false}, none, true);
  EXPECT_EQ(refused.clearance, 0.0);
  EXPECT_EQ(refused.closest, "needle/phantom");
  ASSERT_FALSE(refused.under_threshold.empty());
  EXPECT_EQ(refused.under_threshold.back(), (std::pair<std::string, double>{"needle/phantom", 0.0}));
  EXPECT_TRUE(allowed.under_threshold.empty()) << allowed.under_threshold.front().first;
  // 3 cm above the skin the needle is no contact at all.
  const ClearanceSample above = monitor.measure(KDL::Frame(needle.M, KDL::Vector(0, 0, 0.13)), probe, {true, false},
                                                none, false);
  EXPECT_GT(above.contacts[1], 0.02);
}

TEST(ClearanceMonitor, TheMeasuredJointsDecideTheArmsBranchNotTheModelsSeed) {
  // kUr5Joints is elbow down (q3 > 0) with the upper arm reaching over the phantom's edge; the
  // UR5 model's own seed is elbow up and reaches the same probe pose clear of it.
  ClearanceMonitor measured_branch(scene(), kContacts), model_branch(scene(), kContacts);
  const KDL::Frame needle = needlePose(kIsurJoints), probe = probePose(kUr5Joints);
  std::vector<KDL::JntArray> measured(2);
  measured[measured_branch.robotIndex("isur")] = kIsurJoints;
  measured[measured_branch.robotIndex("ur5")] = kUr5Joints;
  const ClearanceSample seeded = measured_branch.measure(needle, probe, {true, false}, measured, true);
  const ClearanceSample model = model_branch.measure(needle, probe, {true, false}, std::vector<KDL::JntArray>(2), true);
  EXPECT_EQ(seeded.clearance, 0.0);
  EXPECT_EQ(seeded.closest, "ur5_upper_arm/phantom");
  EXPECT_GT(model.clearance, 0.01) << model.closest;
}

TEST(ClearanceMonitor, RefusesAContactWhoseObjectTheSceneLacksAndAnUndeclaredSceneContact) {
  try {
    ClearanceMonitor monitor(scene(), {{"probe on skin", "us_probe", "phantom"}, {"tool", "scalpel", "phantom"}});
    FAIL() << "no scalpel in the scene";
  } catch (const std::invalid_argument& e) {
    EXPECT_CONTAINS(e.what(), "allowed contact 'tool': the planning scene has no object 'scalpel'");
  }
  try {
    ClearanceMonitor monitor(scene(), {{"needle in tissue", "needle", "phantom"}});
    FAIL() << "the scene allows us_probe/phantom";
  } catch (const std::invalid_argument& e) {
    EXPECT_CONTAINS(e.what(), "the scene allows contact us_probe/phantom but it is not among the declared");
  }
}

}  // namespace
}  // namespace cobra::puncturing
