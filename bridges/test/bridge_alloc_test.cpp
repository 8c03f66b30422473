// The bridges' updateHook allocates nothing (ARCHITECTURE §4), with live far ends exchanging data.
#include <gtest/gtest.h>

#include "bridge_test_support.hpp"
#include "cobra/bridges/isur_robot_bridge.hpp"
#include "cobra/bridges/omni_phantom_bridge.hpp"
#include "cobra/bridges/sim/isur_controller.hpp"
#include "cobra/bridges/sim/omni_server.hpp"
#include "cobra/test_support/counting_new.hpp"

namespace cobra::bridges {
namespace {

using namespace std::chrono_literals;
using cobra::test_support::allocationsDuring;

TEST(BridgeAllocations, IsurUpdateAllocatesNothingWhileStatesAndCommandsFlow) {
  IsurSimController controller(IsurSimControllerOptions{});
  controller.start();
  test::UniqueShm shm;
  core::LockstepClock clock;
  ISURRobotBridge bridge("isur");
  clock.add(bridge, 1ms);
  core::OutputPort<KDL::JntArray> des{"des", "", "m, rad", KDL::JntArray(8)};
  core::InputPort<KDL::JntArray> meas{"meas", "", "m, rad"};
  core::connectPorts(des, bridge.port("desJointPosition"));
  core::connectPorts(bridge.port("measJointPosition"), meas);
  bridge.setProperty("shm_name", shm.name);
  bridge.setProperty("run_server", true);
  bridge.setProperty("controller_port", static_cast<int>(controller.local().port()));
  bridge.setProperty("timeout", 0.005);  // so that the timeout and restore paths run too
  ASSERT_TRUE(bridge.configure());
  ASSERT_TRUE(bridge.start());
  KDL::JntArray q = controller.jointPositions();
  des.write(q);
  ASSERT_TRUE(test::pollUntil(clock, [&] { return bridge.call<int>("acceptedCount") > 0; }));
  long allocations = 0;
  for (int i = 0; i < 200; ++i) {
    q(0) += 1e-5;
    des.write(q);  // outside the measured region: the writer's own port is not under test
    allocations += allocationsDuring([&] { clock.advance(1ms); });
    std::this_thread::sleep_for(200us);
  }
  EXPECT_EQ(allocations, 0);
}

TEST(BridgeAllocations, TwoToolIsurUpdateAllocatesNothingWithPosesActuationsAndEventsFlowing) {
  IsurSimControllerOptions options;
  options.tools = 2;
  options.initial_joints = test::suturingStart();
  options.actuation_time = 0.02;
  ASSERT_EQ(options.initial_joints.size(), 14U);
  IsurSimController controller(options);
  controller.start();
  test::UniqueShm shm;
  core::LockstepClock clock;
  ISURRobotBridge bridge("isur");
  clock.add(bridge, 1ms);
  bridge.setProperty("shm_name", shm.name);
  bridge.setProperty("run_server", true);
  bridge.setProperty("controller_port", static_cast<int>(controller.local().port()));
  bridge.setProperty("joints", 14);
  bridge.setProperty("tools", 2);
  bridge.setProperty("timeout", 0.005);  // so that the timeout and restore paths run too
  ASSERT_TRUE(bridge.configure());
  core::OutputPort<KDL::Frame> right{"right", "", "m"}, left{"left", "", "m"};
  core::OutputPort<core::Event> requests{"requests", "", ""};
  core::InputPort<KDL::Frame> meas{"meas", "", "m"};
  core::InputPort<int> actuations{"actuations", "", "1"};
  core::connectPorts(right, bridge.port("desRightCartPose"));
  core::connectPorts(left, bridge.port("desLeftCartPose"));
  core::connectPorts(requests, bridge.port("inputEvents"), core::ConnPolicy::buffer(8));
  core::connectPorts(bridge.port("measLeftCartPose"), meas);
  core::connectPorts(bridge.port("endoStitchActuations"), actuations);
  ASSERT_TRUE(bridge.start());
  kinematics::IsurSuturingSolver solver;
  KDL::JntArray q(14);
  for (unsigned i = 0; i < 14; ++i) q(i) = options.initial_joints[i];
  KDL::Frame stitch, gripper;
  ASSERT_EQ(solver.forward(q, stitch, gripper), kinematics::IkStatus::Ok);
  right.write(stitch);
  ASSERT_TRUE(test::pollUntil(clock, [&] { return bridge.call<int>("acceptedCount") > 0; }));
  core::Event actuate;
  actuate.name = "e_actuate_endo_stitch";
  long allocations = 0;
  for (int i = 0; i < 200; ++i) {
    // Outside the measured region: the writers' own ports are not under test.
    stitch.p += KDL::Vector(0.0, 0.0, -1e-5);
    gripper.p += KDL::Vector(1e-5, 0.0, 0.0);
    right.write(stitch);
    left.write(gripper);
    if (i % 20 == 0) requests.write(actuate);
    allocations += allocationsDuring([&] { clock.advance(1ms); });
    std::this_thread::sleep_for(200us);
  }
  EXPECT_EQ(allocations, 0);
  int count = 0;
  ASSERT_NE(actuations.read(count), core::FlowStatus::NoData);
  EXPECT_GT(count, 0) << "the actuation path ran";
}

TEST(BridgeAllocations, OmniUpdateAllocatesNothingWhileStatesAndCommandsFlow) {
  OmniSimServer app(OmniSimServerOptions{});
  app.start();
  core::LockstepClock clock;
  OmniPhantomBridge bridge("omni");
  clock.add(bridge, 1ms);
  core::OutputPort<KDL::Wrench> des{"des", "", "N"};
  core::InputPort<KDL::Frame> meas{"meas", "", "m"};
  core::connectPorts(des, bridge.port("desWrench"));
  core::connectPorts(bridge.port("measCartPose"), meas);
  bridge.setProperty("host_port", static_cast<int>(app.local().port()));
  bridge.setProperty("timeout", 0.005);
  ASSERT_TRUE(bridge.configure());
  ASSERT_TRUE(bridge.start());
  ASSERT_TRUE(test::pollUntil(clock, [&] { return bridge.call<int>("acceptedCount") > 0; }));
  long allocations = 0;
  for (int i = 0; i < 200; ++i) {
    des.write(KDL::Wrench(KDL::Vector(0.001 * i, 0, 0), KDL::Vector::Zero()));
    allocations += allocationsDuring([&] { clock.advance(1ms); });
    std::this_thread::sleep_for(200us);
  }
  EXPECT_EQ(allocations, 0);
  ASSERT_TRUE(bridge.stop());
}

}  // namespace
}  // namespace cobra::bridges
