// IgtlBridge's updateHook allocates nothing (ARCHITECTURE §4) while every path flows: transforms,
// plans, mapped and unmapped requests in; transforms, task state, events and images out. The
// counter is global, so the peer here allocates nothing either once set up: it sends bytes packed
// beforehand by libOpenIGTLink and a thread of its own reads what the bridge sends into a fixed
// buffer.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <thread>

#include "bridge_test_support.hpp"
#include "cobra/bridges/igtl_bridge.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "igtl_test_peer.hpp"

namespace cobra::bridges {
namespace {

using namespace std::chrono_literals;
using cobra::test_support::allocationsDuring;

TEST(IgtlAllocations, UpdateAllocatesNothingWhileEveryPathFlows) {
  core::LockstepClock clock;
  IgtlBridge bridge("igtl");
  clock.add(bridge, 1ms);
  test::EventLog events(bridge);
  bridge.setProperty("port", 0);
  bridge.setProperty("send_period", 0.005);
  bridge.setProperty("send_transforms", "NeedleTip=needleTip");
  bridge.setProperty("receive_transforms", "Registration=abdomenFrame");
  bridge.setProperty("plan_device", "Plan");
  bridge.setProperty("requests", "START=e_nav_start");
  bridge.setProperty("images", "USImage=usImage");
  bridge.setProperty("send_strings", "Refusal=refusal");
  ASSERT_TRUE(bridge.configure());
  core::OutputPort<KDL::Frame> needle{"needle", "", "m"};
  core::InputPort<KDL::Frame> abdomen{"abdomen", "", "m"};
  core::InputPort<types::PointList> plan{"plan_in", "", "m"};
  core::OutputPort<core::TaskState> task{"task", "", ""};
  core::OutputPort<core::Event> nav_events{"nav_events", "", ""};
  core::OutputPort<types::GrayImage> us{"us", "", "m"};
  core::connectPorts(needle, bridge.port("needleTip"));
  core::connectPorts(bridge.port("abdomenFrame"), abdomen);
  core::connectPorts(bridge.port("plan"), plan);
  core::connectPorts(task, bridge.port("taskState"));
  core::connectPorts(nav_events, bridge.port("inputEvents"), core::ConnPolicy::buffer(16));
  core::connectPorts(us, bridge.port("usImage"));
  core::OutputPort<std::string> refusal{"refusal_out", "", ""};
  core::connectPorts(refusal, bridge.port("refusal"), core::ConnPolicy::buffer(4));
  ASSERT_TRUE(bridge.start());
  // A line longer than a short string's inline storage (the bridge reads into reserved storage).
  const std::string line = "navigation refused: navigation plan:3: needle 'n2': target is 30.0 mm from the tumour "
                           "centre, outside its radius 12.0 mm";

  int error = 0;
  FileDescriptor peer = connectTcp(resolve("127.0.0.1", static_cast<std::uint16_t>(bridge.call<int>("localPort"))), 1000, error);
  ASSERT_TRUE(peer.valid()) << error;
  std::atomic<bool> reading{true};
  std::atomic<long> bytes_read{0};
  std::thread reader([&] {
    static std::array<std::uint8_t, 1 << 16> sink;
    while (reading.load()) {
      if (!waitReadable(peer.get(), 5)) continue;
      std::size_t got = 0;
      if (receiveSome(peer.get(), sink, got) == IoResult::Closed) break;
      bytes_read.fetch_add(static_cast<long>(got));
    }
  });
  const std::vector<std::vector<std::uint8_t>> incoming = {
      test::transformBytes("Registration", 0.1F, 1, 2, 3), test::pointBytes("Plan", {{"entry", "plan", 1, 2, 3}}),
      test::stringBytes("Request", "START"), test::stringBytes("Request", "unmapped text"),
      test::transformBytes("Unknown", 0.0F, 1, 2, 3)};
  auto image = std::make_unique<types::GrayImage>();
  image->width = 64;
  image->height = 48;
  const core::TaskState states[2] = {core::TaskState{"root.a"}, core::TaskState{"root.b"}};
  core::Event event;
  event.name = "e_skin_punctured";
  ASSERT_TRUE(test::pollUntil(clock, [&] { return events.last() == "e_igtl_connected"; }));

  long allocations = 0;
  for (int i = 0; i < 300; ++i) {
    // Outside the measured region: the peer's sends and the writers' own ports are not under test.
    ASSERT_EQ(sendAll(peer.get(), incoming[i % incoming.size()], 1000), IoResult::Done);
    needle.write(KDL::Frame(KDL::Vector(0.001 * i, 0, 0)));
    if (i % 10 == 0) task.write(states[(i / 10) % 2]);
    if (i % 7 == 0) nav_events.write(event);
    if (i % 30 == 0) refusal.write(line);
    if (i % 20 == 0) {
      image->pixels[0] = static_cast<std::uint8_t>(i);
      us.write(*image);
    }
    allocations += allocationsDuring([&] { clock.advance(1ms); });
    std::this_thread::sleep_for(300us);
  }
  EXPECT_EQ(allocations, 0);
  reading.store(false);
  reader.join();
  // Every path ran: received and used, dropped (unmapped and unknown device), sent.
  EXPECT_GT(bridge.getProperty<int>("received_messages"), 100);
  EXPECT_GT(bridge.getProperty<int>("dropped_messages"), 50);
  EXPECT_GT(bridge.getProperty<int>("sent_messages"), 50);
  EXPECT_GT(bytes_read.load(), 64 * 48);
  types::PointList list;
  EXPECT_NE(plan.read(list), core::FlowStatus::NoData);
  ASSERT_TRUE(bridge.stop());
}

}  // namespace
}  // namespace cobra::bridges
