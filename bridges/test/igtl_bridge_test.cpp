// IgtlBridge on 127.0.0.1 against peers written on libOpenIGTLink (as 3D Slicer and PLUS are):
// transforms, plans and requests in; transforms, task state, events and images out; every kind of
// bad input dropped and counted while the bridge goes on; peers lost and served again; the client
// role; and the configure-time refusals of malformed mappings.
#include "cobra/bridges/igtl_bridge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "bridge_test_support.hpp"
#include "igtl_test_peer.hpp"

namespace cobra::bridges {
namespace {

using namespace std::chrono_literals;
using test::pollUntil;

/// A libOpenIGTLink client connected to the bridge, with a receive timeout (ms).
struct Peer {
  ::igtl::ClientSocket::Pointer socket = ::igtl::ClientSocket::New();
  explicit Peer(int port) {
    EXPECT_EQ(socket->ConnectToServer("127.0.0.1", port), 0);
    socket->SetReceiveTimeout(3000);
  }
  ~Peer() { socket->CloseSocket(); }
  void send(const std::vector<std::uint8_t>& bytes) { ASSERT_EQ(socket->Send(bytes.data(), static_cast<int>(bytes.size())), 1); }
  /// The next message of `type` (others skipped), or empty after the timeout.
  std::vector<std::uint8_t> next(const std::string& type, std::string* device = nullptr) {
    for (;;) {
      std::string t, d;
      auto bytes = test::receiveMessage(socket.GetPointer(), t, d);
      if (bytes.empty() || t == type) {
        if (device) *device = d;
        return bytes;
      }
    }
  }
};

struct Rig {
  core::LockstepClock clock;
  std::unique_ptr<IgtlBridge> bridge = std::make_unique<IgtlBridge>("igtl");
  test::EventLog events{*bridge};
  core::OutputPort<KDL::Frame> needle{"needle", "", "m"};
  core::OutputPort<KDL::Frame> probe{"probe", "", "m"};
  core::InputPort<KDL::Frame> abdomen{"abdomen", "", "m"};
  core::InputPort<types::PointList> plan{"plan_in", "", "m"};
  core::OutputPort<core::TaskState> task{"task", "", ""};
  core::OutputPort<core::Event> nav_events{"nav_events", "", ""};
  core::OutputPort<types::GrayImage> us{"us", "", "m"};
  core::OutputPort<std::string> refusal{"refusal_out", "", ""};

  explicit Rig(double send_period = 0.01, int max_message_bytes = 4096) {
    clock.add(*bridge, 1ms);
    bridge->setProperty("port", 0);
    bridge->setProperty("send_period", send_period);
    bridge->setProperty("max_message_bytes", max_message_bytes);
    bridge->setProperty("send_transforms", "NeedleTip=needleTip, Probe=probePose");
    bridge->setProperty("receive_transforms", "Registration=abdomenFrame");
    bridge->setProperty("plan_device", "Plan");
    bridge->setProperty("requests", "START=e_nav_start, ABORT=e_nav_abort");
    bridge->setProperty("images", "USImage=usImage");
    bridge->setProperty("send_strings", "Refusal=refusal");
  }
  void up() {
    const core::Result configured = bridge->configure();
    ASSERT_TRUE(configured) << configured.message;
    core::connectPorts(needle, bridge->port("needleTip"));
    core::connectPorts(probe, bridge->port("probePose"));
    core::connectPorts(bridge->port("abdomenFrame"), abdomen);
    core::connectPorts(bridge->port("plan"), plan);
    core::connectPorts(task, bridge->port("taskState"));
    core::connectPorts(nav_events, bridge->port("inputEvents"), core::ConnPolicy::buffer(16));
    core::connectPorts(us, bridge->port("usImage"));
    core::connectPorts(refusal, bridge->port("refusal"), core::ConnPolicy::buffer(4));
    ASSERT_TRUE(bridge->start());
  }
  ~Rig() { (void)bridge->stop(); }
  int port() { return bridge->call<int>("localPort"); }
  int count(const char* property) { return bridge->getProperty<int>(property); }
  std::string reason() { return bridge->getProperty<std::string>("dropped_reason"); }
  bool saw(const std::string& event) {
    events.drain();
    return std::find(events.names.begin(), events.names.end(), event) != events.names.end();
  }
  /// Polls until the bridge has seen a peer connect (e_igtl_connected) `n` times.
  bool connected(std::size_t n = 1) {
    return pollUntil(clock, [&] {
      events.drain();
      return static_cast<std::size_t>(std::count(events.names.begin(), events.names.end(), "e_igtl_connected")) >= n;
    });
  }
};

TEST(IgtlBridge, ATransformFromThePeerReachesItsOutPortInMetres) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  peer.send(test::transformBytes("Registration", 0.25F, 12.5F, -40.25F, 100.75F));
  KDL::Frame frame;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.abdomen.read(frame) != core::FlowStatus::NoData; }));
  EXPECT_NEAR(frame.p.x(), 0.0125, 1e-9);
  EXPECT_NEAR(frame.p.y(), -0.04025, 1e-9);
  EXPECT_NEAR(frame.p.z(), 0.10075, 1e-9);
  EXPECT_NEAR(frame.M(1, 0), std::sin(0.25F), 1e-7);
  EXPECT_NEAR(frame.M(0, 1), -std::sin(0.25F), 1e-7);
  EXPECT_EQ(rig.count("received_messages"), 1);
  EXPECT_EQ(rig.count("dropped_messages"), 0);
}

TEST(IgtlBridge, APointListOfThePlanDeviceBecomesThePlan) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  peer.send(test::pointBytes("Plan", {{"entry", "needle path", 10, 20, 30}, {"target", "needle path", 15, 25, 95}}));
  types::PointList list;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.plan.read(list) != core::FlowStatus::NoData; }));
  ASSERT_EQ(list.count, 2U);
  EXPECT_EQ(list.points[0].name, "entry");
  EXPECT_EQ(list.points[1].group, "needle path");
  EXPECT_NEAR(list.points[1].position.z(), 0.095, 1e-9);
  // A POINT of another device is no plan: dropped as an unknown device.
  peer.send(test::pointBytes("Fiducials", {{"f", "g", 1, 2, 3}}));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 1; }));
  EXPECT_EQ(rig.reason(), "unknown_device");
}

// A plan of more points than a PointList holds is dropped whole, never cut to its first ones.
TEST(IgtlBridge, APlanOfMorePointsThanAPointListHoldsIsDroppedWhole) {
  Rig rig(0.01, 1 << 16);  // room for the message: it is the plan's length that is refused
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  std::vector<test::PeerPoint> too_many(types::PointList::kCapacity + 1, {"p", "plan", 1, 2, 3});
  peer.send(test::pointBytes("Plan", too_many));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 1; }));
  EXPECT_EQ(rig.reason(), "plan_too_long");
  types::PointList list;
  EXPECT_EQ(rig.plan.read(list), core::FlowStatus::NoData);
}

TEST(IgtlBridge, AMappedRequestEmitsItsEventAndAnyOtherTextIsDroppedWithoutEvent) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  peer.send(test::stringBytes("Request", "START"));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_nav_start"); }));
  peer.send(test::stringBytes("Request", "start"));  // keys are exact
  peer.send(test::stringBytes("Request", "e_nav_abort"));  // an event's name is no key either
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 2; }));
  EXPECT_EQ(rig.reason(), "unmapped");
  peer.send(test::stringBytes("Request", "ABORT"));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_nav_abort"); }));
  rig.events.drain();
  EXPECT_EQ(std::count(rig.events.names.begin(), rig.events.names.end(), "e_nav_start"), 1);
  EXPECT_EQ(std::count(rig.events.names.begin(), rig.events.names.end(), "e_nav_abort"), 1);
  EXPECT_EQ(rig.count("received_messages"), 2);
}

TEST(IgtlBridge, BadCrcOversizedAndUnknownMessagesAreDroppedAndTheConnectionGoesOn) {
  Rig rig(0.01, 1024);
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  auto bad_crc = test::transformBytes("Registration", 0.0F, 1, 2, 3);
  bad_crc.back() ^= 0x01;
  peer.send(bad_crc);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 1; }));
  EXPECT_EQ(rig.reason(), "bad_crc");
  std::vector<test::PeerPoint> many(10, {"p", "g", 1, 2, 3});  // 58 + 1360 bytes > 1024
  peer.send(test::pointBytes("Plan", many));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 2; }));
  EXPECT_EQ(rig.reason(), "oversized");
  peer.send(test::positionBytes("Tracker"));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 3; }));
  EXPECT_EQ(rig.reason(), "unknown_type");
  peer.send(test::transformBytes("Unmapped", 0.0F, 1, 2, 3));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("dropped_messages") == 4; }));
  EXPECT_EQ(rig.reason(), "unknown_device");
  // The same connection still works: a good message after the bad ones arrives.
  peer.send(test::transformBytes("Registration", 0.0F, 1, 2, 3));
  KDL::Frame frame;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.abdomen.read(frame) != core::FlowStatus::NoData; }));
  EXPECT_NEAR(frame.p.z(), 0.003, 1e-9);
  EXPECT_FALSE(rig.saw("e_igtl_peer_lost"));
}

TEST(IgtlBridge, GarbageLosesTheConnectionWhichIsCountedAndANewPeerIsServed) {
  Rig rig;
  rig.up();
  {
    Peer peer(rig.port());
    ASSERT_TRUE(rig.connected());
    std::vector<std::uint8_t> garbage(200);
    std::mt19937 rng(7);
    for (auto& b : garbage) b = static_cast<std::uint8_t>(rng());
    peer.send(garbage);
    ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_igtl_peer_lost"); }));
  }
  EXPECT_EQ(rig.count("dropped_messages"), 1);
  EXPECT_EQ(rig.reason(), "bad_header");
  Peer again(rig.port());
  ASSERT_TRUE(rig.connected(2));
  again.send(test::transformBytes("Registration", 0.0F, 4, 5, 6));
  KDL::Frame frame;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.abdomen.read(frame) != core::FlowStatus::NoData; }));
  EXPECT_NEAR(frame.p.x(), 0.004, 1e-9);
}

// A header whose body size no message has (a desynchronised stream): closed at once, not skipped
// for ever while the connection looks alive.
TEST(IgtlBridge, AHeaderWithAnAbsurdBodySizeLosesTheConnection) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  auto bytes = test::transformBytes("Registration", 0.0F, 1, 2, 3);
  // body_size: bytes 42-49 of the header, big-endian; 2^40 bytes.
  for (std::size_t i = 42; i < 50; ++i) bytes[i] = 0;
  bytes[44] = 0x01;
  peer.send(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 58));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_igtl_peer_lost"); }));
  EXPECT_EQ(rig.reason(), "bad_header");
}

TEST(IgtlBridge, APeerClosingMidMessageIsLostAndTheNextOneIsServed) {
  Rig rig;
  rig.up();
  {
    Peer peer(rig.port());
    ASSERT_TRUE(rig.connected());
    auto bytes = test::transformBytes("Registration", 0.0F, 1, 2, 3);
    bytes.resize(bytes.size() - 10);
    peer.send(bytes);
  }
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_igtl_peer_lost"); }));
  EXPECT_EQ(rig.reason(), "truncated");
  Peer again(rig.port());
  ASSERT_TRUE(rig.connected(2));
  again.send(test::stringBytes("Request", "START"));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_nav_start"); }));
}

TEST(IgtlBridge, ASilentPeerIsLostAfterThePeerTimeout) {
  Rig rig;
  rig.bridge->setProperty("peer_timeout", 0.05);
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_igtl_peer_lost"); }));
  std::string type, device;
  EXPECT_TRUE(test::receiveMessage(peer.socket.GetPointer(), type, device).empty()) << "the bridge closed it";
}

TEST(IgtlBridge, SendsEachTransformEverySendPeriodInMillimetres) {
  Rig rig(0.01);
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  rig.needle.write(KDL::Frame(KDL::Rotation::RotX(0.5), KDL::Vector(0.1, -0.2, 0.3)));
  for (int i = 0; i < 40; ++i) rig.clock.advance(1ms);  // 40 ms of the bridge's time
  std::vector<double> stamps;
  for (int i = 0; i < 4; ++i) {
    std::string device;
    const auto bytes = peer.next("TRANSFORM", &device);
    ASSERT_FALSE(bytes.empty());
    EXPECT_EQ(device, "NeedleTip") << "only connected ports with data are sent";
    auto m = test::unpack<::igtl::TransformMessage>(bytes);
    ASSERT_TRUE(m);
    ::igtl::Matrix4x4 matrix;
    m->GetMatrix(matrix);
    EXPECT_FLOAT_EQ(matrix[0][3], 100.0F);
    EXPECT_FLOAT_EQ(matrix[1][3], -200.0F);
    EXPECT_FLOAT_EQ(matrix[2][3], 300.0F);
    EXPECT_NEAR(matrix[2][1], std::sin(0.5), 1e-6);
    ::igtl::TimeStamp::Pointer ts = ::igtl::TimeStamp::New();
    m->GetTimeStamp(ts);
    stamps.push_back(ts->GetTimeStamp());
  }
  for (std::size_t i = 1; i < stamps.size(); ++i) EXPECT_NEAR(stamps[i] - stamps[i - 1], 0.01, 1e-6) << i;
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("sent_messages") >= 4; }));
}

TEST(IgtlBridge, SendsTheTaskStateAsStatusOnChangeAndEventsAsStrings) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  rig.task.write(core::TaskState{"root.planning"});
  rig.clock.advance(1ms);
  rig.task.write(core::TaskState{"root.planning"});  // no change: no message
  rig.clock.advance(1ms);
  rig.task.write(core::TaskState{"root.puncturing.insert"});
  rig.nav_events.write(core::Event{"e_skin_punctured", "monitor", 0ns});
  rig.clock.advance(1ms);
  std::string device;
  auto first = test::unpack<::igtl::StatusMessage>(peer.next("STATUS", &device));
  ASSERT_TRUE(first);
  EXPECT_EQ(device, "TaskState");
  EXPECT_STREQ(first->GetStatusString(), "root.planning");
  EXPECT_EQ(first->GetCode(), 1);
  auto second = test::unpack<::igtl::StatusMessage>(peer.next("STATUS"));
  ASSERT_TRUE(second);
  EXPECT_STREQ(second->GetStatusString(), "root.puncturing.insert");
  auto event = test::unpack<::igtl::StringMessage>(peer.next("STRING", &device));
  ASSERT_TRUE(event);
  EXPECT_EQ(device, "Event");
  EXPECT_STREQ(event->GetString(), "e_skin_punctured");
}

TEST(IgtlBridge, EachNewLineOfAStringPortIsSentOnceAsAStringOfItsDevice) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  rig.refusal.write("needle n2 (2 of 2): target outside the tumour");
  rig.clock.advance(1ms);
  rig.clock.advance(1ms);  // no new line: nothing more
  rig.refusal.write(std::string(300, 'x'));  // longer than a STRING keeps: its first 255 characters
  rig.clock.advance(1ms);
  std::string device;
  auto first = test::unpack<::igtl::StringMessage>(peer.next("STRING", &device));
  ASSERT_TRUE(first);
  EXPECT_EQ(device, "Refusal");
  EXPECT_STREQ(first->GetString(), "needle n2 (2 of 2): target outside the tumour");
  auto second = test::unpack<::igtl::StringMessage>(peer.next("STRING", &device));
  ASSERT_TRUE(second);
  EXPECT_EQ(device, "Refusal");
  EXPECT_EQ(std::string(second->GetString()), std::string(255, 'x'));
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.count("sent_messages") >= 2; }));
  EXPECT_EQ(rig.count("sent_messages"), 2);
}

TEST(IgtlBridge, PendingMessagesIsWhatTheLinkHasNotWrittenYetAndAStopStillWritesIt) {
  Rig rig;
  EXPECT_EQ(rig.bridge->call<int>("pendingMessages"), 0);  // not configured: no link
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  for (int i = 0; i < 12; ++i) {
    core::Event event;
    event.name.assign("e_line_" + std::to_string(i));
    rig.nav_events.write(event);
  }
  rig.clock.advance(1ms);  // 12 STRING messages queued in one update (the connection buffers 16)
  EXPECT_LE(rig.bridge->call<int>("pendingMessages"), 12);
  ASSERT_TRUE(rig.bridge->stop());
  EXPECT_EQ(rig.bridge->call<int>("pendingMessages"), 0);
  for (int i = 0; i < 12; ++i) {
    auto event = test::unpack<::igtl::StringMessage>(peer.next("STRING"));
    ASSERT_TRUE(event) << i;
    EXPECT_EQ(std::string(event->GetString()), "e_line_" + std::to_string(i));
  }
}

TEST(IgtlBridge, ANewPeerGetsTheCurrentTaskStateAtOnce) {
  Rig rig;
  rig.up();
  rig.task.write(core::TaskState{"root.navigating"});  // no peer yet: sent to no one
  rig.clock.advance(1ms);
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  std::string device;
  auto status = test::unpack<::igtl::StatusMessage>(peer.next("STATUS", &device));
  ASSERT_TRUE(status);
  EXPECT_EQ(device, "TaskState");
  EXPECT_STREQ(status->GetStatusString(), "root.navigating");
}

TEST(IgtlBridge, SendsAnImageWithItsSizeSpacingAndMatrix) {
  Rig rig;
  rig.up();
  Peer peer(rig.port());
  ASSERT_TRUE(rig.connected());
  auto image = std::make_unique<types::GrayImage>();
  image->width = 160;
  image->height = 120;
  image->spacing_x = 0.3e-3;
  image->spacing_y = 0.2e-3;
  image->pose = KDL::Frame(KDL::Rotation::RotZ(M_PI / 2), KDL::Vector(0.05, 0.0, 0.1));
  for (std::size_t i = 0; i < image->width * image->height; ++i) image->pixels[i] = static_cast<std::uint8_t>(i % 251);
  rig.us.write(*image);
  for (int i = 0; i < 15; ++i) rig.clock.advance(1ms);
  auto m = test::unpack<::igtl::ImageMessage>(peer.next("IMAGE"));
  ASSERT_TRUE(m);
  int size[3];
  m->GetDimensions(size);
  EXPECT_EQ(size[0], 160);
  EXPECT_EQ(size[1], 120);
  float spacing[3];
  m->GetSpacing(spacing);
  EXPECT_NEAR(spacing[0], 0.3, 1e-6);
  EXPECT_NEAR(spacing[1], 0.2, 1e-6);
  ::igtl::Matrix4x4 matrix;
  m->GetMatrix(matrix);
  EXPECT_NEAR(matrix[1][0], 1.0, 1e-6);   // columns along world y
  EXPECT_NEAR(matrix[0][1], -1.0, 1e-6);  // rows along world -x
  // The centre: the corner + 79.5 columns * 0.3 mm along y, 59.5 rows * 0.2 mm along -x.
  EXPECT_NEAR(matrix[0][3], 50.0 - 59.5 * 0.2, 1e-3);
  EXPECT_NEAR(matrix[1][3], 79.5 * 0.3, 1e-3);
  EXPECT_NEAR(matrix[2][3], 100.0, 1e-3);
  const auto* pixels = static_cast<const std::uint8_t*>(m->GetScalarPointer());
  EXPECT_TRUE(std::equal(pixels, pixels + 160 * 120, image->pixels.begin()));
}

TEST(IgtlBridge, AsAClientItConnectsToTheServerAndServesItLikeAPeer) {
  ::igtl::ServerSocket::Pointer server = ::igtl::ServerSocket::New();
  ASSERT_EQ(server->CreateServer(0), 0);
  Rig rig;
  rig.bridge->setProperty("role", "client");
  rig.bridge->setProperty("port", server->GetServerPort());
  rig.up();
  ::igtl::ClientSocket::Pointer socket;
  for (int i = 0; i < 100 && !socket; ++i) socket = server->WaitForConnection(50);
  ASSERT_TRUE(socket);
  socket->SetReceiveTimeout(3000);
  ASSERT_TRUE(rig.connected());
  const auto request = test::stringBytes("Request", "START");
  ASSERT_EQ(socket->Send(request.data(), static_cast<int>(request.size())), 1);
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_nav_start"); }));
  rig.probe.write(KDL::Frame(KDL::Vector(0.01, 0.02, 0.03)));
  for (int i = 0; i < 15; ++i) rig.clock.advance(1ms);
  std::string type, device;
  const auto bytes = test::receiveMessage(socket.GetPointer(), type, device);
  EXPECT_EQ(type, "TRANSFORM");
  EXPECT_EQ(device, "Probe");
  socket->CloseSocket();
  ASSERT_TRUE(pollUntil(rig.clock, [&] { return rig.saw("e_igtl_peer_lost"); }));
  // The client connects again.
  ::igtl::ClientSocket::Pointer again;
  for (int i = 0; i < 100 && !again; ++i) again = server->WaitForConnection(50);
  ASSERT_TRUE(again);
  ASSERT_TRUE(rig.connected(2));
}

std::string refusal(const char* property, const char* value) {
  IgtlBridge bridge("nav");
  bridge.setProperty("port", 0);
  bridge.setProperty(property, value);
  const core::Result r = bridge.configure();
  EXPECT_FALSE(r);
  return r.message;
}

TEST(IgtlBridge, RefusesMalformedMappingsNamingComponentPropertyAndEntry) {
  EXPECT_EQ(refusal("send_transforms", "NeedleTip=needleTip, Probe"),
            "component 'nav': property send_transforms, entry 'Probe': expected DEVICE=port (a device name of 1 to 20 "
            "printable characters, a port name of letters, digits and '_'), entries separated by ','");
  EXPECT_EQ(refusal("receive_transforms", "Registration=2frame"),
            "component 'nav': property receive_transforms, entry 'Registration=2frame': expected DEVICE=port (a device "
            "name of 1 to 20 printable characters, a port name of letters, digits and '_'), entries separated by ','");
  EXPECT_EQ(refusal("requests", "START=nav_start"),
            "component 'nav': property requests, entry 'START=nav_start': expected KEY=e_event (a key of 1 to 20 "
            "printable characters, an event name starting with e_), entries separated by ','");
  EXPECT_EQ(refusal("receive_transforms", "A=frame, A=other"),
            "component 'nav': property receive_transforms, entry 'A=other': the name 'A' is mapped twice");
  EXPECT_EQ(refusal("images", "AVeryLongDeviceNameOf25Ch=us"),
            "component 'nav': property images, entry 'AVeryLongDeviceNameOf25Ch=us': expected DEVICE=port (a device "
            "name of 1 to 20 printable characters, a port name of letters, digits and '_'), entries separated by ','");
  EXPECT_EQ(refusal("role", "peer"), "component 'nav': property role, entry 'peer': expected \"server\" or \"client\"");
}

TEST(IgtlBridge, RefusesAMappingOntoAPortOfAnotherTypeAndLeavesNoPortBehind) {
  EXPECT_EQ(refusal("receive_transforms", "Registration=plan"),
            "component 'nav': property receive_transforms, entry 'Registration=plan': the port 'plan' exists already "
            "(a Geometry.PointList out-port); expected a new port name for a KDL.Frame out-port");
  EXPECT_EQ(refusal("send_transforms", "Tip=taskState"),
            "component 'nav': property send_transforms, entry 'Tip=taskState': the port 'taskState' exists already "
            "(a TaskState in-port); expected a new port name for a KDL.Frame in-port");
  IgtlBridge bridge("nav");
  bridge.setProperty("port", 0);
  bridge.setProperty("send_transforms", "Tip=tip");
  bridge.setProperty("images", "US=tip");  // the port made by the first mapping: refused
  const core::Result r = bridge.configure();
  EXPECT_FALSE(r);
  EXPECT_EQ(r.message, "component 'nav': property images, entry 'US=tip': the port 'tip' exists already (a KDL.Frame "
                       "in-port); expected a new port name for a Imaging.GrayImage in-port");
  EXPECT_EQ(bridge.findPort("tip"), nullptr) << "a refused configure leaves no mapped port";
}

}  // namespace
}  // namespace cobra::bridges
