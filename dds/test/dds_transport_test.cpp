// The dds transport in one process: two DomainParticipants (as two processes would have) and one
// participant carrying both ends of a connectPorts; data and buffer semantics and flow status as
// local ports; the error messages of bad policies; type and QoS mismatches reported with both
// ends named. Each test uses its own DDS domain (ctest runs tests in parallel).
#include "cobra/dds/dds_transport.hpp"

#include <gtest/gtest.h>

#include "cobra/core/error.hpp"
#include "cobra/core/port.hpp"
#include "cobra/test_support/test_support.hpp"
#include "dds_test_support.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;
using test::event;
using test::pollUntil;
using test::RegisteredTransport;

TEST(DdsTransport, DataConnectionBetweenTwoParticipantsKeepsTheLatestFrame) {
  RegisteredTransport a("dds_data_a", 111, "cobra_a");
  RegisteredTransport b("dds_data_b", 111, "cobra_b");
  core::OutputPort<KDL::Frame> out("pose", "needle pose", "m");
  core::InputPort<KDL::Frame> in("pose", "needle pose", "m");
  core::connectToTransport(out, a.policy("needle/pose"));
  core::connectToTransport(in, b.policy("/needle/pose"));  // a leading '/' names the same topic
  ASSERT_TRUE(a.transport->waitForMatch("needle/pose", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("needle/pose", 5s));

  KDL::Frame got;
  EXPECT_EQ(in.read(got), core::FlowStatus::NoData);
  const KDL::Frame first(KDL::Rotation::RPY(0.1, -0.2, 0.3), KDL::Vector(0.4, -0.05, 0.12));
  EXPECT_EQ(out.write(first), core::WriteStatus::Written);
  ASSERT_TRUE(pollUntil([&] { return in.read(got) == core::FlowStatus::NewData; }));
  EXPECT_TRUE(KDL::Equal(got, first, 1e-12));
  KDL::Frame again;
  EXPECT_EQ(in.read(again), core::FlowStatus::OldData);
  EXPECT_TRUE(KDL::Equal(again, first, 1e-12));

  // Several writes before a read: a data connection gives the latest only.
  for (int i = 1; i <= 20; ++i) out.write(KDL::Frame(KDL::Vector(0.01 * i, 0, 0)));
  ASSERT_TRUE(pollUntil([&] {
    in.read(got);
    return std::abs(got.p.x() - 0.2) < 1e-12;
  }));
  EXPECT_EQ(in.read(got), core::FlowStatus::OldData);
}

TEST(DdsTransport, BufferConnectionDeliversEveryEventInOrder) {
  RegisteredTransport a("dds_buffer_a", 112, "cobra_a");
  RegisteredTransport b("dds_buffer_b", 112, "cobra_b");
  core::OutputPort<core::Event> out("events", "", "");
  core::InputPort<core::Event> in("inputEvents", "", "");
  core::ConnPolicy policy = core::ConnPolicy::buffer(32);
  policy.options = {{"reliability", "reliable"}, {"depth", "32"}};
  core::connectToTransport(out, a.policy("needle/events", policy));
  core::connectToTransport(in, b.policy("needle/events", policy));
  ASSERT_TRUE(a.transport->waitForMatch("needle/events", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("needle/events", 5s));

  for (int i = 0; i < 20; ++i) ASSERT_EQ(out.write(event("e_" + std::to_string(i))), core::WriteStatus::Written);
  std::vector<std::string> names;
  ASSERT_TRUE(pollUntil([&] {
    core::Event e;
    while (in.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names.size() >= 20;
  }));
  ASSERT_EQ(names.size(), 20U);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(names[static_cast<std::size_t>(i)], "e_" + std::to_string(i));
  core::Event last;
  EXPECT_EQ(in.read(last), core::FlowStatus::OldData);
  EXPECT_EQ(last.name, "e_19");
}

TEST(DdsTransport, ConnectPortsThroughTheTransportAndDisconnectBothEnds) {
  RegisteredTransport dds("dds_connect", 113, "cobra");
  core::OutputPort<std::vector<double>> out("q", "", "rad", std::vector<double>(6, 0.0));
  core::InputPort<std::vector<double>> in("q", "", "rad");
  core::connectPorts(out, in, dds.policy("arm/q", core::ConnPolicy::buffer(4)));
  EXPECT_TRUE(out.connectedTo(in));
  EXPECT_TRUE(in.connectedTo(out));
  EXPECT_EQ(out.connections().front()->policy().describe(), "buffer(4) over dds_connect topic 'arm/q'");
  EXPECT_THROW(core::connectPorts(out, in, dds.policy("arm/q")), core::Error);  // already connected
  ASSERT_TRUE(dds.transport->waitForMatch("arm/q", 5s));

  const std::vector<double> q{0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  out.write(q);
  std::vector<double> got;
  ASSERT_TRUE(pollUntil([&] { return in.read(got) == core::FlowStatus::NewData; }));
  EXPECT_EQ(got, q);

  EXPECT_TRUE(core::disconnectPorts(out, in));
  EXPECT_FALSE(out.connected());
  EXPECT_FALSE(in.connected());
  EXPECT_EQ(out.write(q), core::WriteStatus::NotConnected);
  EXPECT_FALSE(core::disconnectPorts(out, in));
}

TEST(DdsTransport, BadPoliciesAreRefusedWithTheKeyAndTheAllowedValues) {
  RegisteredTransport dds("dds_bad", 114, "cobra");
  core::OutputPort<double> out("x", "", "m");
  core::InputPort<double> in("x", "", "m");

  core::ConnPolicy unknown = core::ConnPolicy::data();
  unknown.transport = "nope";
  unknown.topic = "x";
  const std::string unknown_message = test_support::messageOf([&] { core::connectPorts(out, in, unknown); });
  EXPECT_NE(unknown_message.find("cannot connect x (double) to x (double): unknown transport 'nope'; transports: "),
            std::string::npos)
      << unknown_message;
  EXPECT_NE(unknown_message.find("'dds_bad' (Fast DDS, domain 114, from cobra_dds)"), std::string::npos) << unknown_message;

  core::ConnPolicy bad_key = dds.policy("x");
  bad_key.options = {{"relability", "reliable"}};
  EXPECT_EQ(test_support::messageOf([&] { core::connectToTransport(out, bad_key); }),
            "cannot connect x (double) to dds_bad topic 'x': unknown dds qos key 'relability'; allowed keys: "
            "reliability (\"reliable\" or \"best_effort\"), depth (an integer >= 1), lease (s, a number > 0), "
            "durability (\"volatile\" or \"transient_local\")");

  core::ConnPolicy bad_value = dds.policy("x");
  bad_value.options = {{"reliability", "sometimes"}};
  EXPECT_EQ(test_support::messageOf([&] { core::connectToTransport(out, bad_value); }),
            "cannot connect x (double) to dds_bad topic 'x': dds qos.reliability = \"sometimes\": expected "
            "\"reliable\" or \"best_effort\"");
  bad_value.options = {{"depth", "0"}};
  EXPECT_NE(test_support::messageOf([&] { core::connectToTransport(out, bad_value); }).find("expected an integer >= 1"),
            std::string::npos);
  bad_value.options = {{"lease", "-1"}};
  EXPECT_NE(test_support::messageOf([&] { core::connectToTransport(out, bad_value); }).find("a number of seconds > 0"),
            std::string::npos);

  EXPECT_EQ(test_support::messageOf([&] { core::connectToTransport(out, dds.policy("needle pose")); }),
            "cannot connect x (double) to dds_bad topic 'needle pose': dds topic 'needle pose' is not a ROS 2 topic "
            "name: expected letters, digits and '_' in '/'-separated parts, not starting with a digit, e.g. "
            "\"needle/pose\"");
  EXPECT_NE(test_support::messageOf([&] { core::connectToTransport(out, core::ConnPolicy::data()); })
                .find("its connection policy names none"),
            std::string::npos);
  EXPECT_FALSE(out.connected());  // nothing half-made
}

TEST(DdsTransport, OneTopicCarriesOneTypeInAProcess) {
  RegisteredTransport dds("dds_one_type", 115, "cobra");
  core::OutputPort<double> depth("depth", "", "m");
  core::OutputPort<KDL::Frame> pose("pose", "", "m");
  core::connectToTransport(depth, dds.policy("needle/state"));
  EXPECT_EQ(test_support::messageOf([&] { core::connectToTransport(pose, dds.policy("needle/state")); }),
            "cannot connect pose (KDL.Frame) to dds_one_type topic 'needle/state': dds topic 'rt/needle/state' carries "
            "std_msgs::msg::dds_::Float64_ in this process (the writer of depth (double) in this process), but pose "
            "(KDL.Frame) needs geometry_msgs::msg::dds_::Pose_; one topic carries one type: use another topic");
}

TEST(DdsTransport, TypeMismatchBetweenParticipantsIsReportedNamingBothTypes) {
  RegisteredTransport a("dds_types_a", 116, "cobra_a");
  RegisteredTransport b("dds_types_b", 116, "cobra_b");
  core::InputPort<core::Event> problems("problems", "", "");
  core::connectPorts(b.transport->events(), problems, core::ConnPolicy::buffer(8));
  core::OutputPort<double> depth("depth", "", "m");
  core::InputPort<KDL::Frame> pose("pose", "", "m");
  core::connectToTransport(depth, a.policy("needle/tip"));
  core::connectToTransport(pose, b.policy("needle/tip"));

  ASSERT_TRUE(pollUntil([&] { return !a.transport->problems().empty() && !b.transport->problems().empty(); }));
  EXPECT_EQ(a.transport->problems().front(),
            "dds topic 'rt/needle/tip': the two ends' types differ: the writer of depth (double) in this process sends "
            "std_msgs::msg::dds_::Float64_, but a reader in participant 'cobra_b' expects "
            "geometry_msgs::msg::dds_::Pose_; they never connect (use ports of one type on both ends, or another topic)");
  EXPECT_EQ(b.transport->problems().front(),
            "dds topic 'rt/needle/tip': the two ends' types differ: the reader of pose (KDL.Frame) in this process "
            "expects geometry_msgs::msg::dds_::Pose_, but a writer in participant 'cobra_a' sends "
            "std_msgs::msg::dds_::Float64_; they never connect (use ports of one type on both ends, or another topic)");
  core::Event e;
  ASSERT_EQ(problems.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name, "e_dds_type_mismatch");
  EXPECT_EQ(e.source, "rt/needle/tip");
  EXPECT_EQ(b.transport->problems().size(), 1U);  // reported once, not at every discovery message
}

TEST(DdsTransport, IncompatibleQosIsReportedNamingWhatEachEndOffersAndRequests) {
  RegisteredTransport a("dds_qos_a", 117, "cobra_a");
  RegisteredTransport b("dds_qos_b", 117, "cobra_b");
  core::OutputPort<core::Event> out("events", "", "");
  core::InputPort<core::Event> in("inputEvents", "", "");
  core::ConnPolicy offered = core::ConnPolicy::buffer(8);
  offered.options = {{"reliability", "best_effort"}};
  core::ConnPolicy requested = core::ConnPolicy::buffer(8);
  requested.options = {{"reliability", "reliable"}};
  core::connectToTransport(out, a.policy("probe/events", offered));
  core::connectToTransport(in, b.policy("probe/events", requested));

  ASSERT_TRUE(pollUntil([&] { return !a.transport->problems().empty() && !b.transport->problems().empty(); }));
  EXPECT_EQ(a.transport->problems().front(),
            "dds topic 'rt/probe/events': incompatible QoS (reliability): the writer of events (Event) in this process "
            "offers best_effort, volatile, lease infinite, but a reader in participant 'cobra_b' requests reliable, "
            "volatile, lease infinite; they never connect (a reader cannot request more than the writer offers)");
  EXPECT_NE(b.transport->problems().front().find("the reader of inputEvents (Event) in this process requests reliable"),
            std::string::npos)
      << b.transport->problems().front();
  EXPECT_NE(b.transport->problems().front().find("a writer in participant 'cobra_a' offers best_effort"),
            std::string::npos)
      << b.transport->problems().front();
  EXPECT_FALSE(a.transport->waitForMatch("probe/events", 100ms));
}

}  // namespace
}  // namespace cobra::dds
