// ISURRobotBridge + IsurUdpServer against the simulated I-SUR controller and against raw crafted
// datagrams, all over UDP on 127.0.0.1 with ephemeral ports.
#include "cobra/bridges/isur_robot_bridge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <numbers>

#include "bridge_test_support.hpp"
#include "cobra/bridges/sim/isur_controller.hpp"
#include "cobra/test_support/test_support.hpp"

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
  core::InputPort<KDL::Frame> held_pose{"held_pose", "", "m"};
  test::EventLog events{bridge};

  /// Configures and starts the bridge with its in-process server commanding `controller_port`.
  explicit Rig(std::uint16_t controller_port) {
    clock.add(bridge, 1ms);
    core::connectPorts(bridge.port("heldCartPose"), held_pose);
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
  // Nothing malformed, corrupt or out of order; a state older than max_delay (50 ms) is rightly
  // dropped, which happens when the machine is loaded (ThreadSanitizer beside other builds).
  EXPECT_EQ(rig.rejected("all") - rig.rejected("delayed"), 0);
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
  KDL::Frame held;
  EXPECT_EQ(rig.held_pose.read(held), core::FlowStatus::NoData);  // not held before the refusal
  rig.des_pose.write(refused);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return emitted("e_ik_discontinuity") == 1; }));
  // Held: the measured pose, for the producers of the commands to re-sync to.
  ASSERT_EQ(rig.held_pose.read(held), core::FlowStatus::NewData);
  KDL::Frame at_q;
  ASSERT_EQ(solver.forward(q, at_q), kinematics::IkStatus::Ok);
  EXPECT_TRUE(KDL::Equal(held.p, at_q.p, 1e-5)) << "m: where the robot holds";
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
  isur::State two_tools = valid;
  two_tools.tool_count = 2;
  fake.send(fake.frame(two_tools, 106), port);  // wrong tool count: a suturing robot's state
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.rejected("all") == 10; })) << rig.rejected("all");
  EXPECT_EQ(rig.rejected("truncated"), 1);
  EXPECT_EQ(rig.rejected("bad_magic"), 1);
  EXPECT_EQ(rig.rejected("bad_crc"), 1);
  EXPECT_EQ(rig.rejected("non_finite"), 1);
  EXPECT_EQ(rig.rejected("late"), 2);
  EXPECT_EQ(rig.rejected("delayed"), 1);
  EXPECT_EQ(rig.rejected("wrong_joint_count"), 1);
  EXPECT_EQ(rig.rejected("wrong_tool_count"), 1);
  EXPECT_EQ(rig.rejected("bad_length"), 1);
  EXPECT_EQ(rig.bridge.call<int>("acceptedCount"), 1);
  for (int i = 0; i < 5; ++i) rig.clock.advance(1ms);
  EXPECT_TRUE(near(rig.joints(), expected, 0.0)) << "the bridge must keep publishing the last valid state";

  fake.send(fake.frame(other, 107), port);  // valid again
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
  KDL::Frame measured, held_pose;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.meas_pose.read(measured) != core::FlowStatus::NoData; }));
  controller.setSending(false);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.events.last() == "e_comm_timeout"; }));
  KDL::JntArray held;
  EXPECT_NE(rig.meas_joints.read(held), core::FlowStatus::NoData);
  EXPECT_EQ(held.rows(), 8U) << "the last valid state is still published";
  // Timed out: the last measured pose is the held one, in each update, for the commands to re-sync to.
  ASSERT_EQ(rig.held_pose.read(held_pose), core::FlowStatus::NewData);
  (void)rig.meas_pose.read(measured);
  EXPECT_EQ(held_pose, measured);
  rig.clock.advance(1ms);
  EXPECT_EQ(rig.held_pose.read(held_pose), core::FlowStatus::NewData);
  controller.setSending(true);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.events.last() == "e_comm_restored"; }));
  (void)rig.held_pose.read(held_pose);
  rig.clock.advance(1ms);
  EXPECT_NE(rig.held_pose.read(held_pose), core::FlowStatus::NewData) << "restored: no longer held";
}

// The two-tool bridge (tools = 2, the suturing I-SUR) against the simulated two-tool controller.
struct SuturingRig {
  test::UniqueShm shm;
  core::LockstepClock clock;
  ISURRobotBridge bridge{"isur"};
  core::OutputPort<KDL::JntArray> des_joints{"des_joints", "", "m, rad", KDL::JntArray(14)};
  std::array<core::OutputPort<KDL::Frame>, 2> des_pose{{{"des_right", "", "m"}, {"des_left", "", "m"}}};
  core::OutputPort<core::Event> requests{"requests", "", ""};
  core::InputPort<KDL::JntArray> meas_joints{"meas_joints", "", "m, rad"};
  std::array<core::InputPort<KDL::Frame>, 2> meas_pose{{{"meas_right", "", "m"}, {"meas_left", "", "m"}}};
  std::array<core::InputPort<KDL::Wrench>, 2> meas_wrench{{{"wrench_right", "", "N"}, {"wrench_left", "", "N"}}};
  core::InputPort<int> actuations{"actuations", "", "1"};
  test::EventLog events{bridge};

  explicit SuturingRig(std::uint16_t controller_port) {
    clock.add(bridge, 1ms);
    bridge.setProperty("shm_name", shm.name);
    bridge.setProperty("run_server", true);
    bridge.setProperty("controller_port", static_cast<int>(controller_port));
    bridge.setProperty("timeout", 0.05);
    bridge.setProperty("joints", 14);
    bridge.setProperty("tools", 2);
    const core::Result configured = bridge.configure();
    EXPECT_TRUE(configured) << configured.message;
    // The per-tool ports exist once configured with tools = 2.
    core::connectPorts(des_joints, bridge.port("desJointPosition"));
    core::connectPorts(des_pose[0], bridge.port("desRightCartPose"));
    core::connectPorts(des_pose[1], bridge.port("desLeftCartPose"));
    core::connectPorts(requests, bridge.port("inputEvents"), core::ConnPolicy::buffer(8));
    core::connectPorts(bridge.port("measJointPosition"), meas_joints);
    core::connectPorts(bridge.port("measRightCartPose"), meas_pose[0]);
    core::connectPorts(bridge.port("measLeftCartPose"), meas_pose[1]);
    core::connectPorts(bridge.port("measRightWrench"), meas_wrench[0]);
    core::connectPorts(bridge.port("measLeftWrench"), meas_wrench[1]);
    core::connectPorts(bridge.port("endoStitchActuations"), actuations);
    EXPECT_TRUE(bridge.start());
  }
  KDL::JntArray joints() {
    KDL::JntArray q;
    meas_joints.read(q);
    return q;
  }
  void actuate() {
    core::Event e;
    e.name = "e_actuate_endo_stitch";
    requests.write(e);
  }
  long emitted(const char* name) {
    events.drain();
    return std::count(events.names.begin(), events.names.end(), name);
  }
};

IsurSimControllerOptions suturingController() {
  IsurSimControllerOptions options;
  options.tools = 2;
  options.initial_joints = test::suturingStart();
  options.actuation_time = 0.05;
  return options;
}

KDL::JntArray jntArray(const std::vector<double>& q) {
  KDL::JntArray a(static_cast<unsigned>(q.size()));
  for (unsigned i = 0; i < a.rows(); ++i) a(i) = q[i];
  return a;
}

TEST(ISURRobotBridge, WithTwoToolsCarriesFourteenJointsBothToolPosesAndBothWrenches) {
  ASSERT_EQ(test::suturingStart().size(), 14U);
  IsurSimController controller(suturingController());
  controller.start();
  SuturingRig rig(controller.local().port());
  EXPECT_THROW(rig.bridge.port("desCartPose"), core::Error) << "the one-tool ports are gone with tools = 2";
  controller.setExternalWrench(KDL::Wrench(KDL::Vector(0, 0, 2.0), KDL::Vector::Zero()), 0);
  controller.setExternalWrench(KDL::Wrench(KDL::Vector(-1.0, 0, 0), KDL::Vector::Zero()), 1);
  KDL::JntArray target = jntArray(test::suturingStart());
  target(1) += 0.005;   // m: a delta slider
  target(10) += 0.05;   // rad: the gripper arm's third joint
  rig.des_joints.write(target);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return near(rig.joints(), target, 1e-4); }))
      << "measured joints never reached the command";
  kinematics::IsurSuturingSolver solver;
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(rig.joints(), stitch, gripper), kinematics::IkStatus::Ok);
  KDL::Frame right, left;
  ASSERT_NE(rig.meas_pose[0].read(right), core::FlowStatus::NoData);
  ASSERT_NE(rig.meas_pose[1].read(left), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(right.p, stitch.p, 1e-3));
  EXPECT_TRUE(KDL::Equal(left.p, gripper.p, 1e-3));
  EXPECT_GT((right.p - left.p).Norm(), 0.01) << "two different tools";
  KDL::Wrench w_right, w_left;
  ASSERT_NE(rig.meas_wrench[0].read(w_right), core::FlowStatus::NoData);
  ASSERT_NE(rig.meas_wrench[1].read(w_left), core::FlowStatus::NoData);
  EXPECT_NEAR(w_right.force.z(), 2.0, 0.1);  // AtiNano43 / AtiNano17 noise and resolution are far below 0.1 N
  EXPECT_NEAR(w_right.force.x(), 0.0, 0.1);
  EXPECT_NEAR(w_left.force.x(), -1.0, 0.1);
  EXPECT_NEAR(w_left.force.z(), 0.0, 0.1);
  EXPECT_EQ(rig.bridge.call<int>("rejectedCount", std::string("all")), 0);
  EXPECT_EQ(controller.counters().rejected(), 0U);
}

TEST(ISURRobotBridge, WithTwoToolsEachToolFollowsItsCartesianCommandAndAnUncommandedToolStays) {
  IsurSimController controller(suturingController());
  controller.start();
  SuturingRig rig(controller.local().port());
  kinematics::IsurSuturingSolver solver;
  KDL::Frame right0, left0;
  ASSERT_EQ(solver.forward(jntArray(test::suturingStart()), right0, left0), kinematics::IkStatus::Ok);
  const auto commanded = [&](KDL::Frame& right, KDL::Frame& left) {
    return solver.forward(controller.commandedJoints(), right, left) == kinematics::IkStatus::Ok;
  };
  // The right tool (Endo Stitch) alone, 0.1 mm per command: the left keeps its pose although the
  // platform under it moves.
  KDL::Frame right_target = right0;
  for (int k = 1; k <= 20; ++k) {
    right_target.p = right0.p + KDL::Vector(0.0, 0.0, -1e-4 * k);
    rig.des_pose[0].write(right_target);
    ASSERT_TRUE(pollUntil(rig.clock, [&] {
      KDL::Frame r, l;
      return commanded(r, l) && KDL::Equal(r, right_target, 1e-9);
    })) << "right command " << k << " was not applied";
    KDL::Frame r, l;
    ASSERT_TRUE(commanded(r, l));
    ASSERT_TRUE(KDL::Equal(l, left0, 1e-9)) << "the uncommanded left tool moved at " << k;
  }
  // Then both: the left 0.1 mm per command along x, the right held at its last target.
  KDL::Frame left_target = left0;
  for (int k = 1; k <= 20; ++k) {
    left_target.p = left0.p + KDL::Vector(1e-4 * k, 0.0, 0.0);
    rig.des_pose[1].write(left_target);
    ASSERT_TRUE(pollUntil(rig.clock, [&] {
      KDL::Frame r, l;
      return commanded(r, l) && KDL::Equal(l, left_target, 1e-9) && KDL::Equal(r, right_target, 1e-9);
    })) << "left command " << k << " was not applied";
  }
  rig.events.drain();
  for (const std::string& name : rig.events.names)
    EXPECT_EQ(name.rfind("e_ik_", 0), std::string::npos) << "no refusal on continuous paths: " << name;
  KDL::Frame right, left;
  ASSERT_TRUE(pollUntil(rig.clock, [&] {
    return rig.meas_pose[0].read(right) != core::FlowStatus::NoData &&
           rig.meas_pose[1].read(left) != core::FlowStatus::NoData && KDL::Equal(right, right_target, 1e-4) &&
           KDL::Equal(left, left_target, 1e-4);
  })) << "the measured poses never reached the commands";
}

TEST(ISURRobotBridge, WithTwoToolsACommandBeyondTheVelocityBoundIsRefusedAndTheRobotHolds) {
  IsurSimController controller(suturingController());
  controller.start();
  SuturingRig rig(controller.local().port());
  kinematics::IsurSuturingSolver solver;
  const KDL::JntArray start = jntArray(test::suturingStart());
  KDL::Frame right0, left0;
  ASSERT_EQ(solver.forward(start, right0, left0), kinematics::IkStatus::Ok);
  KDL::Frame far = left0;
  far.p += KDL::Vector(0.0, 0.02, 0.0);  // 2 cm in one 2 ms period: 10 m/s
  rig.des_pose[1].write(far);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.emitted("e_ik_discontinuity") == 1; }));
  for (int i = 0; i < 200; ++i) {
    rig.clock.advance(1ms);
    ASSERT_TRUE(near(controller.commandedJoints(), start, 0.0)) << "the command changed at " << i;
  }
  EXPECT_EQ(rig.emitted("e_ik_discontinuity"), 1) << "once per refusal episode";
  KDL::Frame unreachable = right0;
  unreachable.p += KDL::Vector(0.0, 0.0, -5.0);  // 5 m below: out of reach
  rig.des_pose[0].write(unreachable);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.emitted("e_ik_failed") == 1; }));
  // Acceptable commands again: both tools where they are.
  rig.des_pose[0].write(right0);
  rig.des_pose[1].write(left0);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.emitted("e_ik_solved") == 1; }));
  EXPECT_TRUE(near(controller.commandedJoints(), start, 1e-9));
}

TEST(ISURRobotBridge, WithTwoToolsTheActuateEventActuatesTheEndoStitchOnceAndItsCountComesBack) {
  IsurSimControllerOptions options = suturingController();
  options.actuation_time = 0.3;  // s: far longer than the two requests below take, even on a loaded machine
  IsurSimController controller(options);
  controller.start();
  SuturingRig rig(controller.local().port());
  rig.des_joints.write(jntArray(test::suturingStart()));  // the controller learns where to send states
  int count = -1;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.actuations.read(count) != core::FlowStatus::NoData; }));
  EXPECT_EQ(count, 0);
  rig.actuate();
  rig.clock.advance(1ms);
  rig.actuate();  // while the first is unanswered or running: refused
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.emitted("e_endo_stitch_actuated") == 1; }));
  rig.actuations.read(count);
  EXPECT_EQ(count, 1);
  EXPECT_EQ(controller.actuations(), 1U);
  EXPECT_EQ(rig.emitted("e_endo_stitch_busy"), 1);
  // The server repeats a request until a state acknowledges it: no second actuation, no refusal.
  EXPECT_FALSE(pollUntil(rig.clock, [] { return false; }, 100));
  EXPECT_EQ(controller.actuations(), 1U);
  EXPECT_EQ(rig.emitted("e_endo_stitch_busy"), 1);
  rig.actuate();
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.emitted("e_endo_stitch_actuated") == 2; }));
  rig.actuations.read(count);
  EXPECT_EQ(count, 2);
  EXPECT_EQ(controller.actuations(), 2U);
}

TEST(IsurSimController, HandlesEachActuationRequestNumberOnce) {
  IsurSimControllerOptions options = suturingController();
  options.actuation_time = 0.01;
  IsurSimController controller(options);
  controller.start();
  UdpSocket server("127.0.0.1", 0);
  std::uint32_t sequence = 0;
  const auto request = [&](std::uint32_t number) {
    isur::Command c;
    c.type = isur::MessageType::ToolActuation;
    c.actuation = {.tool = 0, .request = number};
    std::vector<std::uint8_t> bytes(isur::kMaxFrameSize);
    bytes.resize(isur::encode(c, {++sequence, static_cast<std::uint64_t>(steadyNanoseconds())}, bytes));
    ASSERT_TRUE(server.sendTo(controller.local(), bytes));
  };
  request(7);
  ASSERT_TRUE(test_support::waitUntil([&] { return controller.actuations() == 1; }));
  request(7);  // a repeat of a number already handled, after its actuation ended: ignored
  request(7);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // 10 actuation times
  EXPECT_EQ(controller.actuations(), 1U);
  request(8);
  ASSERT_TRUE(test_support::waitUntil([&] { return controller.actuations() == 2; }));
  EXPECT_EQ(controller.counters().rejected(), 0U);
}

TEST(ISURRobotBridge, AOneToolControllerRefusesAnActuationAndATwoToolBridgeRejectsItsStates) {
  IsurSimController controller(IsurSimControllerOptions{});  // the puncturing robot: 8 joints, 1 tool
  controller.start();
  SuturingRig rig(controller.local().port());
  rig.des_joints.write(jntArray(test::suturingStart()));  // 14 joints: wrong_joint_count at the controller
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return controller.counters().get(wire::DecodeStatus::WrongJointCount) > 0; }));
  rig.des_pose[0].write(KDL::Frame(KDL::Vector(0.0, 0.0, -0.3)));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return controller.counters().get(wire::DecodeStatus::WrongToolCount) > 0; }));
  rig.actuate();  // a valid datagram: the controller now sends states (8 joints, 1 tool)
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.bridge.call<int>("rejectedCount", std::string("all")) > 0; }));
  EXPECT_EQ(rig.bridge.call<int>("acceptedCount"), 0);
  EXPECT_EQ(controller.actuations(), 0U);
}

TEST(ISURRobotBridge, ConfiguringAnotherToolCountSwapsThePerToolPorts) {
  test::UniqueShm shm;
  ISURRobotBridge bridge("isur");
  bridge.setProperty("shm_name", shm.name);
  EXPECT_NO_THROW(bridge.port("desCartPose"));
  EXPECT_THROW(bridge.port("desRightCartPose"), core::Error);
  bridge.setProperty("tools", 2);
  ASSERT_TRUE(bridge.configure());
  for (const char* name : {"desRightCartPose", "desLeftCartPose", "measRightCartPose", "measLeftCartPose",
                           "measRightWrench", "measLeftWrench", "inputEvents", "endoStitchActuations",
                           "desJointPosition", "measJointPosition"})
    EXPECT_NO_THROW(bridge.port(name)) << name;
  for (const char* name : {"desCartPose", "measCartPose", "measWrench"})
    EXPECT_THROW(bridge.port(name), core::Error) << name;
  ASSERT_TRUE(bridge.cleanup());
  bridge.setProperty("tools", 1);
  ASSERT_TRUE(bridge.configure());
  for (const char* name : {"desCartPose", "measCartPose", "measWrench"}) EXPECT_NO_THROW(bridge.port(name)) << name;
  for (const char* name : {"desRightCartPose", "inputEvents", "endoStitchActuations"})
    EXPECT_THROW(bridge.port(name), core::Error) << name;
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
  EXPECT_THROW(bridge.setProperty("tools", 3), core::Error);
  bridge.setProperty("run_server", false);
  bridge.setProperty("tools", 2);
  bridge.setProperty("actuate_event", std::string());
  r = bridge.configure();
  ASSERT_FALSE(r);
  EXPECT_NE(r.message.find("property actuate_event is ''"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace cobra::bridges
