// Conversions between cobra's port types and their ROS 2 messages: round trips (seeded random,
// 500 values per type), units unchanged (SI on both sides), the ROS 2 type names, and the
// quaternion rules (normalised on reading, identity for a zero quaternion).
#include "cobra/dds/conversions.hpp"
#include "cobra/dds/codec.hpp"

#include <gtest/gtest.h>

#include <random>

namespace cobra::dds {
namespace {

constexpr int kSamples = 500;

KDL::Rotation randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  double x = n(rng), y = n(rng), z = n(rng), w = n(rng);
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  return KDL::Rotation::Quaternion(x / norm, y / norm, z / norm, w / norm);
}

KDL::Vector randomVector(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  return {u(rng), u(rng), u(rng)};
}

TEST(DdsConversions, TypeNamesAreRos2Names) {
  EXPECT_EQ(wireTypeName<double>(), "std_msgs::msg::dds_::Float64_");
  EXPECT_EQ(wireTypeName<std::vector<double>>(), "std_msgs::msg::dds_::Float64MultiArray_");
  EXPECT_EQ(wireTypeName<std::string>(), "std_msgs::msg::dds_::String_");
  EXPECT_EQ(wireTypeName<KDL::Frame>(), "geometry_msgs::msg::dds_::Pose_");
  EXPECT_EQ(wireTypeName<KDL::Twist>(), "geometry_msgs::msg::dds_::Twist_");
  EXPECT_EQ(wireTypeName<KDL::Wrench>(), "geometry_msgs::msg::dds_::Wrench_");
  EXPECT_EQ(wireTypeName<KDL::JntArray>(), "cobra_msgs::msg::dds_::JntArray_");
  EXPECT_EQ(wireTypeName<core::Event>(), "cobra_msgs::msg::dds_::Event_");
}

TEST(DdsConversions, FrameRoundTripKeepsPositionInMetresAndRotation) {
  std::mt19937 rng(21);
  for (int i = 0; i < kSamples; ++i) {
    const KDL::Frame frame(randomRotation(rng), randomVector(rng));
    geometry_msgs::msg::Pose pose;
    toMsg(frame, pose);
    EXPECT_EQ(pose.position().x(), frame.p.x());
    EXPECT_EQ(pose.position().y(), frame.p.y());
    EXPECT_EQ(pose.position().z(), frame.p.z());
    const double qn = std::hypot(std::hypot(pose.orientation().x(), pose.orientation().y()),
                                 std::hypot(pose.orientation().z(), pose.orientation().w()));
    EXPECT_NEAR(qn, 1.0, 1e-12);
    KDL::Frame back;
    fromMsg(pose, back);
    EXPECT_TRUE(KDL::Equal(back, frame, 1e-12)) << "sample " << i;
  }
}

TEST(DdsConversions, QuaternionAgreesWithTheRotationMatrixFormula) {
  // Independent of KDL: R(q) for a unit quaternion, written out.
  std::mt19937 rng(7);
  for (int i = 0; i < kSamples; ++i) {
    const KDL::Rotation r = randomRotation(rng);
    geometry_msgs::msg::Quaternion q;
    toMsg(r, q);
    const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
    const double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) EXPECT_NEAR(m[row][col], r(row, col), 1e-12);
  }
}

TEST(DdsConversions, NonUnitQuaternionIsNormalisedAndZeroIsIdentity) {
  geometry_msgs::msg::Quaternion q;
  q.x(0.0);
  q.y(0.0);
  q.z(2.0);  // 180 degrees about z, scaled by 2
  q.w(0.0);
  KDL::Rotation r;
  fromMsg(q, r);
  EXPECT_TRUE(KDL::Equal(r, KDL::Rotation::RotZ(M_PI), 1e-12));
  fromMsg(geometry_msgs::msg::Quaternion{}, r);  // all zero: a message whose orientation was never set
  EXPECT_TRUE(KDL::Equal(r, KDL::Rotation::Identity(), 1e-15));
}

TEST(DdsConversions, TwistAndWrenchRoundTripFieldByField) {
  std::mt19937 rng(3);
  for (int i = 0; i < kSamples; ++i) {
    const KDL::Twist twist(randomVector(rng), randomVector(rng));
    geometry_msgs::msg::Twist t;
    toMsg(twist, t);
    EXPECT_EQ(t.linear().x(), twist.vel.x());     // m/s
    EXPECT_EQ(t.angular().z(), twist.rot.z());    // rad/s
    KDL::Twist twist_back;
    fromMsg(t, twist_back);
    EXPECT_TRUE(KDL::Equal(twist_back, twist, 1e-15));

    const KDL::Wrench wrench(randomVector(rng), randomVector(rng));
    geometry_msgs::msg::Wrench w;
    toMsg(wrench, w);
    EXPECT_EQ(w.force().y(), wrench.force.y());    // N
    EXPECT_EQ(w.torque().x(), wrench.torque.x());  // N·m
    KDL::Wrench wrench_back;
    fromMsg(w, wrench_back);
    EXPECT_TRUE(KDL::Equal(wrench_back, wrench, 1e-15));
  }
}

TEST(DdsConversions, SequencesRoundTripWithTheirLength) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> length(0, 14);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < kSamples; ++i) {
    std::vector<double> values(static_cast<std::size_t>(length(rng)));
    for (double& v : values) v = u(rng);
    std_msgs::msg::Float64MultiArray array;
    toMsg(values, array);
    EXPECT_TRUE(array.layout().dim().empty());
    std::vector<double> values_back{1.0, 2.0};
    fromMsg(array, values_back);
    EXPECT_EQ(values_back, values);

    KDL::JntArray q(static_cast<unsigned int>(values.size()));
    for (std::size_t j = 0; j < values.size(); ++j) q(static_cast<unsigned int>(j)) = values[j];
    cobra_msgs::msg::JntArray msg;
    toMsg(q, msg);
    KDL::JntArray q_back(3);
    fromMsg(msg, q_back);
    ASSERT_EQ(q_back.rows(), q.rows());
    EXPECT_TRUE(q_back == q);
  }
}

TEST(DdsConversions, EventKeepsNameSourceAndStampAndTruncatesLikeThePort) {
  core::Event event;
  event.name = "e_needle_inserted";
  event.source = "NeedleTaskSup";
  event.stamp = std::chrono::nanoseconds(163'000'000'001);
  cobra_msgs::msg::Event msg;
  toMsg(event, msg);
  EXPECT_EQ(msg.name(), "e_needle_inserted");
  EXPECT_EQ(msg.stamp_ns(), 163'000'000'001);
  core::Event back;
  fromMsg(msg, back);
  EXPECT_EQ(back, event);
  msg.name(std::string(100, 'x'));
  fromMsg(msg, back);
  EXPECT_EQ(back.name.size(), 63U);

  core::TaskState state;
  state.path = "root.puncturing.insert";
  cobra_msgs::msg::TaskState state_msg;
  toMsg(state, state_msg);
  core::TaskState state_back;
  fromMsg(state_msg, state_back);
  EXPECT_EQ(state_back, state);
}

TEST(DdsConversions, QuaternionsOfTinyOrHugeComponentsAreNormalisedExactly) {
  // Their squares under- or overflow: found by the record fuzzer (a rotation that changed when
  // sent again).
  for (const double scale : {3.4e-161, 1e-300, 1e150, 1e300}) {
    geometry_msgs::msg::Quaternion q;
    q.x(-scale);
    q.y(-scale);
    q.z(-scale);
    q.w(-scale);
    KDL::Rotation r;
    fromMsg(q, r);
    EXPECT_TRUE(KDL::Equal(r, KDL::Rotation::Quaternion(0.5, 0.5, 0.5, 0.5), 1e-15)) << scale;
    geometry_msgs::msg::Quaternion again;
    toMsg(r, again);
    KDL::Rotation back;
    fromMsg(again, back);
    EXPECT_TRUE(KDL::Equal(back, r, 1e-15)) << scale;
  }  geometry_msgs::msg::Quaternion nan;  // one component not a number: the identity, as a zero one
  nan.x(5e-310);
  nan.y(std::nan(""));
  nan.z(7e-307);
  KDL::Rotation r = KDL::Rotation::RotX(1.0);
  fromMsg(nan, r);
  EXPECT_TRUE(KDL::Equal(r, KDL::Rotation::Identity(), 1e-15));
}

TEST(DdsConversions, ReceivedTextEndsAtItsFirstNul) {
  // Fast CDR writes strings as C strings: bytes a peer sends after a '\0' are not text.
  std_msgs::msg::String s;
  s.data(std::string("ab\0cd", 5));
  std::string text = "old";
  fromMsg(s, text);
  EXPECT_EQ(text, "ab");
  cobra_msgs::msg::Event e;
  e.name(std::string("e_go\0x", 6));
  e.source(std::string("\0src", 4));
  core::Event event;
  fromMsg(e, event);
  EXPECT_EQ(event.name, "e_go");
  EXPECT_EQ(event.source, "");
}

TEST(DdsConversions, ScalarsAndTextRoundTrip) {
  std_msgs::msg::Float64 f;
  toMsg(-2.5e-3, f);
  double d = 0;
  fromMsg(f, d);
  EXPECT_EQ(d, -2.5e-3);
  std_msgs::msg::Int32 i32;
  toMsg(-7, i32);
  int i = 0;
  fromMsg(i32, i);
  EXPECT_EQ(i, -7);
  std_msgs::msg::Bool b;
  toMsg(true, b);
  bool flag = false;
  fromMsg(b, flag);
  EXPECT_TRUE(flag);
  std_msgs::msg::String s;
  toMsg(std::string("needle 1 placed"), s);
  std::string text;
  fromMsg(s, text);
  EXPECT_EQ(text, "needle 1 placed");
}

}  // namespace
}  // namespace cobra::dds
