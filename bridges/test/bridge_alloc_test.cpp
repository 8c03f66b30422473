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
