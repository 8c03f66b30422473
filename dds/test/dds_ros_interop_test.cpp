// ROS 2 interoperability (what the dds transport's topic and type names are for): a plain Fast DDS
// subscriber, built only from the type support fastddsgen generates from
// geometry_msgs/msg/Pose.idl, receives the pose a cobra port publishes, on the topic and type names
// a ROS 2 node uses ("rt/needle/pose", "geometry_msgs::msg::dds_::Pose_"); and a plain Fast DDS
// publisher feeds a cobra input port.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <gtest/gtest.h>

#include "cobra/core/port.hpp"
#include "dds_test_support.hpp"
#include "geometry_msgs/msg/PosePubSubTypes.h"

namespace cobra::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
using namespace std::chrono_literals;

/// A participant that knows nothing of cobra: what a ROS 2 node's rmw would create.
struct PlainParticipant {
  explicit PlainParticipant(int domain) {
    participant = fdds::DomainParticipantFactory::get_instance()->create_participant(domain, fdds::PARTICIPANT_QOS_DEFAULT);
    type.register_type(participant);
    topic = participant->create_topic("rt/needle/pose", type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  }
  ~PlainParticipant() {
    participant->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant);
  }
  fdds::DomainParticipant* participant;
  fdds::TypeSupport type{new geometry_msgs::msg::PosePubSubType()};
  fdds::Topic* topic;
};

TEST(DdsRosInterop, APlainFastDdsSubscriberOfGeometryMsgsPoseReceivesCobrasPose) {
  PlainParticipant plain(119);
  ASSERT_EQ(plain.type.get_type_name(), "geometry_msgs::msg::dds_::Pose_");
  fdds::Subscriber* subscriber = plain.participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  fdds::DataReader* reader = subscriber->create_datareader(plain.topic, fdds::DATAREADER_QOS_DEFAULT);
  ASSERT_NE(reader, nullptr);

  test::RegisteredTransport dds("dds", 119, "cobra");
  core::OutputPort<KDL::Frame> pose("pose", "needle tip pose", "m");
  core::connectToTransport(pose, dds.policy("needle/pose"));
  ASSERT_TRUE(dds.transport->waitForMatch("needle/pose", 5s));
  ASSERT_TRUE(test::pollUntil([&] {  // and the plain reader has matched cobra's writer
    fdds::SubscriptionMatchedStatus matched;
    return reader->get_subscription_matched_status(matched) == ReturnCode_t::RETCODE_OK && matched.current_count > 0;
  }));

  const KDL::Frame frame(KDL::Rotation::RPY(0.3, 0.2, -0.1), KDL::Vector(0.25, -0.1, 0.05));
  pose.write(frame);
  geometry_msgs::msg::Pose msg;
  fdds::SampleInfo info;
  ASSERT_TRUE(test::pollUntil([&] { return reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK; }));
  EXPECT_EQ(msg.position().x(), 0.25);
  EXPECT_EQ(msg.position().y(), -0.1);
  EXPECT_EQ(msg.position().z(), 0.05);
  double x = 0, y = 0, z = 0, w = 0;
  frame.M.GetQuaternion(x, y, z, w);
  EXPECT_NEAR(msg.orientation().x(), x, 1e-15);
  EXPECT_NEAR(msg.orientation().y(), y, 1e-15);
  EXPECT_NEAR(msg.orientation().z(), z, 1e-15);
  EXPECT_NEAR(msg.orientation().w(), w, 1e-15);
}

TEST(DdsRosInterop, APlainFastDdsPublisherOfGeometryMsgsPoseFeedsACobraInput) {
  PlainParticipant plain(120);
  fdds::Publisher* publisher = plain.participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  fdds::DataWriter* writer = publisher->create_datawriter(plain.topic, fdds::DATAWRITER_QOS_DEFAULT);
  ASSERT_NE(writer, nullptr);

  test::RegisteredTransport dds("dds", 120, "cobra");
  core::InputPort<KDL::Frame> pose("pose", "needle tip pose", "m");
  core::connectToTransport(pose, dds.policy("needle/pose"));
  ASSERT_TRUE(dds.transport->waitForMatch("needle/pose", 5s));
  // Discovery is two-sided: the plain writer must have matched cobra's reader too, or a volatile
  // sample written before is never sent to it (seen once in 40 runs with six tests in parallel).
  ASSERT_TRUE(test::pollUntil([&] {
    fdds::PublicationMatchedStatus matched;
    return writer->get_publication_matched_status(matched) == ReturnCode_t::RETCODE_OK && matched.current_count > 0;
  }));

  geometry_msgs::msg::Pose msg;
  msg.position().x(1.5);
  msg.orientation().z(std::sin(0.25));  // 0.5 rad about z
  msg.orientation().w(std::cos(0.25));
  writer->write(&msg);
  KDL::Frame got;
  ASSERT_TRUE(test::pollUntil([&] { return pose.read(got) == core::FlowStatus::NewData; }));
  EXPECT_TRUE(KDL::Equal(got, KDL::Frame(KDL::Rotation::RotZ(0.5), KDL::Vector(1.5, 0, 0)), 1e-12));
}

}  // namespace
}  // namespace cobra::dds
