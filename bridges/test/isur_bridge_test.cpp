// ISURRobotBridge + IsurUdpServer against the simulated I-SUR controller and against raw crafted
// datagrams, all over UDP on 127.0.0.1 with ephemeral ports.
#include "cobra/bridges/isur_robot_bridge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numbers>

#include "bridge_test_support.hpp"
#include "cobra/bridges/sim/isur_controller.hpp"

namespace cobra::bridges {
namespace {

using namespace std::chrono_literals;
using test::pollUntil;

struct Rig {
  test::UniqueShm shm;
  core::LockstepClock clock;
  ISURRobotBridge bridge{"isur"};
  core::OutputPort<KDL::JntArray> des_joints{"des_joints", "", "m, rad", KDL::JntArray(8)};
  core::OutputPort<KDL::Frame> des_pose{"des_pose", "", "m"};
  core::InputPort<KDL::JntArray> meas_joints{"meas_joints", "", "m, rad"};
  core::InputPort<KDL::Frame> meas_pose{"meas_pose", "", "m"};
  core::InputPort<KDL::Wrench> meas_wrench{"meas_wrench", "", "N"};
  test::EventLog events{bridge};

  /// Configures and starts the bridge with its in-process server commanding `controller_port`.
  explicit Rig(std::uint16_t controller_port) {
    clock.add(bridge, 1ms);
    core::connectPorts(des_joints, bridge.port("desJointPosition"));
    core::connectPorts(des_pose, bridge.port("desCartPose"));
    core::connectPorts(bridge.port("measJointPosition"), meas_joints);
    core::connectPorts(bridge.port("measCartPose"), meas_pose);
    core::connectPorts(bridge.port("measWrench"), meas_wrench);
    bridge.setProperty("shm_name", shm.name);
    bridge.setProperty("run_server", true);
    bridge.setProperty("controller_port", static_cast<int>(controller_port));
    bridge.setProperty("timeout", 0.05);
    const core::Result configured = bridge.configure();
    EXPECT_TRUE(configured) << configured.message;
    EXPECT_TRUE(bridge.start());
  }
  KDL::JntArray joints() {
    KDL::JntArray q;
    meas_joints.read(q);
    return q;
  }
  int rejected(const char* reason) { return bridge.call<int>("rejectedCount", std::string(reason)); }
};

bool near(const KDL::JntArray& a, const KDL::JntArray& b, double tolerance) {
  if (a.rows() != b.rows()) return false;
  for (unsigned i = 0; i < a.rows(); ++i)
    if (std::abs(a(i) - b(i)) > tolerance) return false;
  return true;
}

TEST(ISURRobotBridge, CommandedJointsReachTheSimulatedControllerAndItsStateComesBack) {
  IsurSimController controller(IsurSimControllerOptions{});
  controller.start();
  Rig rig(controller.local().port());
  const KDL::JntArray start = controller.jointPositions();
  KDL::JntArray target = start;
  target(0) += 0.01;  // m
  target(5) += 0.2;   // rad
  controller.setExternalWrench(KDL::Wrench(KDL::Vector(0, 0, 2.0), KDL::Vector::Zero()));
  rig.des_joints.write(target);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return near(rig.joints(), target, 1e-4); }))
      << "measured joints never reached the command";
  EXPECT_TRUE(near(controller.commandedJoints(), target, 1e-12));
  kinematics::IsurPuncturingSolver solver;
  KDL::Frame expected, measured;
  ASSERT_EQ(solver.forward(rig.joints(), expected), kinematics::IkStatus::Ok);
  ASSERT_NE(rig.meas_pose.read(measured), core::FlowStatus::NoData);
  KDL::JntArray q_now = rig.joints();
  ASSERT_EQ(solver.forward(q_now, expected), kinematics::IkStatus::Ok);
  EXPECT_TRUE(KDL::Equal(measured.p, expected.p, 1e-3));
  KDL::Wrench wrench;
  ASSERT_NE(rig.meas_wrench.read(wrench), core::FlowStatus::NoData);
  EXPECT_NEAR(wrench.force.z(), 2.0, 0.1);  // AtiNano17 noise and resolution are far below 0.1 N
  EXPECT_GT(rig.bridge.call<int>("acceptedCount"), 0);
  EXPECT_EQ(rig.rejected("all"), 0);
  EXPECT_EQ(controller.counters().rejected(), 0U);
}

TEST(ISURRobotBridge, ACartesianCommandIsSolvedByTheControllerAndTheMeasuredPoseFollows) {
  IsurSimController controller(IsurSimControllerOptions{});
  controller.start();
  Rig rig(controller.local().port());
  kinematics::IsurPuncturingSolver solver;
  const KDL::JntArray start = controller.jointPositions();
  // A path in 100 commands (0.1 mm and 1 mrad each: the controller accepts up to 1 m/s, 1 rad/s
  // over its 2 ms period from its previous command), each sent once the previous one is applied.
  KDL::JntArray q = start;
  KDL::Frame target;
  for (int k = 1; k <= 100; ++k) {
    q(1) = start(1) + 0.0001 * k;
    q(6) = start(6) - 0.001 * k;
    ASSERT_EQ(solver.forward(q, target), kinematics::IkStatus::Ok);
    rig.des_pose.write(target);
    ASSERT_TRUE(pollUntil(rig.clock, [&] {
      KDL::Frame commanded;
      return solver.forward(controller.commandedJoints(), commanded) == kinematics::IkStatus::Ok &&
             KDL::Equal(commanded, target, 1e-9);
    })) << "command " << k << " was not applied";
  }
  rig.events.drain();
  for (const std::string& name : rig.events.names)
    EXPECT_EQ(name.rfind("e_ik_", 0), std::string::npos) << "no refusal on a continuous path: " << name;
  KDL::Frame measured;
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    return rig.meas_pose.read(measured) != core::FlowStatus::NoData && KDL::Equal(measured, target, 1e-4);
  })) << "measured pose never reached the Cartesian command";
}

TEST(ISURRobotBridge, ACommandAcrossTheWristSingularityIsRefusedOnceTheRobotHoldsThenFollowsAgain) {
  IsurSimController controller(IsurSimControllerOptions{});
  controller.start();
  Rig rig(controller.local().port());
  // First, in joint space, to a needle 0.3° short of vertical (pitch q6 + q7 = 90° - 0.005 rad).
  KDL::JntArray q = controller.jointPositions();
  q(5) = std::numbers::pi / 4 - 0.005;
  q(6) = std::numbers::pi / 4;
  rig.des_joints.write(q);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return near(controller.jointPositions(), q, 1e-6); }));
  // Then a pose tilted 0.3° past vertical: on the robot's IK branch, yaw and roll turn by π.
  kinematics::IsurPuncturingSolver solver;
  KDL::JntArray across = q;
  across(5) += 0.005;
  across(6) += 0.005;
  KDL::Frame refused;
  ASSERT_EQ(solver.forward(across, refused), kinematics::IkStatus::Ok);
  // Events seen so far with this name (a loaded machine may add e_comm_timeout / e_comm_restored).
  const auto emitted = [&](const char* name) {
    rig.events.drain();
    return std::count(rig.events.names.begin(), rig.events.names.end(), name);
  };
  rig.des_pose.write(refused);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return emitted("e_ik_discontinuity") == 1; }));
  for (int i = 0; i < 500; ++i) {
    rig.clock.advance(1ms);
    ASSERT_TRUE(near(controller.commandedJoints(), q, 0.0)) << "the command changed at " << i;
    ASSERT_TRUE(near(controller.jointPositions(), q, 1e-6)) << "the robot moved at " << i;  // 1 encoder count
  }
  EXPECT_EQ(emitted("e_ik_discontinuity"), 1);
  EXPECT_EQ(emitted("e_ik_failed"), 0);
  // An acceptable command: 0.1 mm from where the needle is.
  KDL::Frame here;
  ASSERT_EQ(solver.forward(q, here), kinematics::IkStatus::Ok);
  here.p += KDL::Vector(0.0, 0.0, 1e-4);
  rig.des_pose.write(here);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return emitted("e_ik_solved") == 1; }));
  KDL::Frame measured;
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    return rig.meas_pose.read(measured) != core::FlowStatus::NoData && KDL::Equal(measured.p, here.p, 2e-6);
  })) << "the measured pose never reached the acceptable command";
}

// A test socket plays the controller: it sends crafted state datagrams to the server.
struct FakeController {
  UdpSocket socket{"127.0.0.1", 0};
  std::uint32_t sequence = 100;
  isur::State state() {
    isur::State s;
    s.joint_count = 8;
    s.flags = isur::kPoseValid;
    for (std::size_t i = 0; i < 8; ++i) s.joints[i] = 0.01 * static_cast<double>(i + 1);
    return s;
  }
  std::vector<std::uint8_t> frame(const isur::State& s, std::uint32_t seq, std::int64_t age_ns = 0) {
    std::vector<std::uint8_t> out(isur::kMaxFrameSize);
    out.resize(isur::encode(s, {seq, static_cast<std::uint64_t>(steadyNanoseconds() - age_ns)}, out));
    return out;
  }
  void send(const std::vector<std::uint8_t>& bytes, std::uint16_t port) {
    ASSERT_TRUE(socket.sendTo(resolve("127.0.0.1", port), bytes));
  }
};

TEST(ISURRobotBridge, MalformedTruncatedCorruptLateAndDelayedStatesAreCountedAndTheLastValidOneIsKept) {
  FakeController fake;
  Rig rig(fake.socket.local().port());
  const auto port = static_cast<std::uint16_t>(rig.bridge.call<int>("serverPort"));
  ASSERT_GT(port, 0);
  isur::State valid = fake.state();
  fake.send(fake.frame(valid, 100), port);
  KDL::JntArray expected(8);
  for (unsigned i = 0; i < 8; ++i) expected(i) = valid.joints[i];
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return near(rig.joints(), expected, 0.0); }));

  const auto good = fake.frame(valid, 101);
  fake.send(std::vector<std::uint8_t>(good.begin(), good.begin() + 30), port);  // truncated
  auto bad = good;
  bad[1] = 'X';
  fake.send(bad, port);  // bad magic
  bad = good;
  bad[50] ^= 0x01;
  fake.send(bad, port);  // bad CRC
  isur::State nan = valid;
  nan.joints[2] = std::numeric_limits<double>::quiet_NaN();
  fake.send(fake.frame(nan, 102), port);  // non-finite
  isur::State other = valid;
  other.joints[0] = 0.5;
  fake.send(fake.frame(other, 100), port);  // late: a sequence number already accepted
  fake.send(fake.frame(other, 60), port);   // late: older
  fake.send(fake.frame(other, 103, 1'000'000'000), port);  // delayed: sent 1 s ago
  isur::State six = valid;
  six.joint_count = 6;
  fake.send(fake.frame(six, 104), port);  // wrong joint count
  fake.send(std::vector<std::uint8_t>(2000, 0xAB), port);  // oversized garbage
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.rejected("all") == 9; })) << rig.rejected("all");
  EXPECT_EQ(rig.rejected("truncated"), 1);
  EXPECT_EQ(rig.rejected("bad_magic"), 1);
  EXPECT_EQ(rig.rejected("bad_crc"), 1);
  EXPECT_EQ(rig.rejected("non_finite"), 1);
  EXPECT_EQ(rig.rejected("late"), 2);
  EXPECT_EQ(rig.rejected("delayed"), 1);
  EXPECT_EQ(rig.rejected("wrong_joint_count"), 1);
  EXPECT_EQ(rig.rejected("bad_length"), 1);
  EXPECT_EQ(rig.bridge.call<int>("acceptedCount"), 1);
  for (int i = 0; i < 5; ++i) rig.clock.advance(1ms);
  EXPECT_TRUE(near(rig.joints(), expected, 0.0)) << "the bridge must keep publishing the last valid state";

  fake.send(fake.frame(other, 105), port);  // valid again
  expected(0) = 0.5;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return near(rig.joints(), expected, 0.0); }));
  EXPECT_THROW(rig.rejected("nonsense"), core::Error);
}

TEST(ISURRobotBridge, RaisesCommTimeoutWhenTheControllerFallsSilentAndCommRestoredWhenItSpeaksAgain) {
  IsurSimController controller(IsurSimControllerOptions{});
  controller.start();
  Rig rig(controller.local().port());
  rig.des_joints.write(controller.jointPositions());  // the controller learns where to send states
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.joints().rows() == 8; }));
  const KDL::JntArray last = rig.joints();
  controller.setSending(false);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.events.last() == "e_comm_timeout"; }));
  KDL::JntArray held;
  EXPECT_NE(rig.meas_joints.read(held), core::FlowStatus::NoData);
  EXPECT_EQ(held.rows(), 8U) << "the last valid state is still published";
  controller.setSending(true);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.events.last() == "e_comm_restored"; }));
}

TEST(ISURRobotBridge, ConfigurationErrorsNameTheProperty) {
  ISURRobotBridge bridge("isur");
  bridge.setProperty("shm_name", "no_slash");
  core::Result r = bridge.configure();
  ASSERT_FALSE(r);
  EXPECT_NE(r.message.find("shared memory 'no_slash'"), std::string::npos) << r.message;
  test::UniqueShm shm;
  bridge.setProperty("shm_name", shm.name);
  bridge.setProperty("run_server", true);
  r = bridge.configure();
  ASSERT_FALSE(r);
  EXPECT_NE(r.message.find("controller_port is 0"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace cobra::bridges
