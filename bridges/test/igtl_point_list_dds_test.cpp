// Geometry.PointList on DDS (its codec where the dds headers are): a plan through the record's
// CDR type support and back, and the ROS 2 type name. No participant: no DDS domain is used.
#include <gtest/gtest.h>

#include "cobra/dds/register_type.hpp"
#include "cobra/types/point_list.hpp"

namespace cobra::types {
namespace {

using eprosima::fastrtps::rtps::SerializedPayload_t;

TEST(PointListDds, APlanCrossesTheWireAndBack) {
  PointList sent;
  sent.add("entry", "needle path", KDL::Vector(0.1, -0.02, 0.05));
  sent.add("target\nline", "needle\tpath", KDL::Vector(0.12, 0.0, 0.11));
  dds::DdsCodec<PointList>::Msg msg;
  dds::DdsCodec<PointList>::toMsg(sent, msg);
  dds::DdsCodec<PointList>::PubSub type;
  SerializedPayload_t payload(type.m_typeSize);
  ASSERT_LE(type.getSerializedSizeProvider(&msg)(), payload.max_size);
  ASSERT_TRUE(type.serialize(&msg, &payload));
  dds::DdsCodec<PointList>::Msg read;
  ASSERT_TRUE(type.deserialize(&payload, &read));
  PointList got;
  dds::DdsCodec<PointList>::fromMsg(read, got);
  ASSERT_EQ(got.count, 2U);
  EXPECT_EQ(got.points[0], sent.points[0]);
  EXPECT_EQ(got.points[1].name, "target line") << "a newline in a name travels as a space";
  EXPECT_EQ(got.points[1].group, "needle path") << "so does a tab";
  EXPECT_EQ(got.points[1].position, sent.points[1].position);
  PointList empty;
  dds::DdsCodec<PointList>::toMsg(PointList{}, msg);
  dds::DdsCodec<PointList>::fromMsg(msg, empty);
  EXPECT_EQ(empty.count, 0U);
}

TEST(PointListDds, RegistersWithTheRos2NameOfItsWire) {
  dds::registerDdsType<PointList>();
  EXPECT_EQ(dds::wireTypeName<PointList>(), "Geometry::msg::dds_::PointList_");
  const auto types = dds::ddsTypes();
  EXPECT_NE(std::find(types.begin(), types.end(), "Geometry.PointList"), types.end());
}

}  // namespace
}  // namespace cobra::types
