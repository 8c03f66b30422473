// A record type on DDS (record_wire.hpp): its type support serialises it field by field in the
// CDR of fastddsgen's code (a record mirroring geometry_msgs/Vector3 gives its bytes), round-trips
// every kind of field, sizes each sample exactly, refuses short or malformed payloads without
// throwing, and allocates nothing to serialise a record of fixed-size fields and short strings.
#include "cobra/dds/record_wire.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "cobra/dds/codec.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "test_payload.hpp"
#include "test_records.hpp"

namespace cobra::dds::test {
/// Strings one after the other, then 4- and 8-byte fields: each field after a string must be
/// read at its CDR alignment whatever the string's length.
struct TwoLabels {
  std::string first, second;
  int count = 0;
  double depth = 0.0;  // m
};
}  // namespace cobra::dds::test

template <>
struct cobra::core::DataTypeTraits<cobra::dds::test::TwoLabels> : cobra::core::RecordTraits<cobra::dds::test::TwoLabels> {
  using T = cobra::dds::test::TwoLabels;
  static constexpr std::string_view name = "probe_msgs.TwoLabels";
  static constexpr auto fields = std::tuple{field("first", &T::first), field("second", &T::second),
                                            field("count", &T::count, "1"), field("depth", &T::depth, "m")};
};

namespace cobra::dds {
namespace {

using eprosima::fastrtps::rtps::SerializedPayload_t;
using test::Gains;
using test::deserialised;
using test::ProbeReading;
using test::serialised;
using test::Vec3;

TEST(DdsRecordWire, ARecordOfThreeDoublesSerialisesAsGeometryMsgsVector3ByteForByte) {
  static_assert(std::is_same_v<DdsCodec<Vec3>::PubSub, RecordPubSubType<Vec3>>);
  RecordPubSubType<Vec3> record_type;
  geometry_msgs::msg::Vector3PubSubType vector3_type;
  EXPECT_EQ(std::string(record_type.getName()), "probe_msgs::msg::dds_::Vec3_");
  EXPECT_EQ(record_type.m_typeSize, vector3_type.m_typeSize);
  EXPECT_EQ(record_type.is_bounded(), vector3_type.is_bounded());
  EXPECT_FALSE(record_type.m_isGetKeyDefined);

  std::mt19937 random(20240611);  // 200 seeded values, including negative zero and extremes
  std::uniform_real_distribution<double> any(-1e6, 1e6);
  for (int i = 0; i < 200; ++i) {
    Vec3 v{any(random), any(random), i == 0 ? -0.0 : any(random)};
    if (i == 1) v = {std::numeric_limits<double>::max(), std::numeric_limits<double>::denorm_min(), -1.0};
    geometry_msgs::msg::Vector3 msg;
    msg.x(v.x);
    msg.y(v.y);
    msg.z(v.z);
    const auto ours = serialised(record_type, v);
    const auto theirs = serialised(vector3_type, msg);
    ASSERT_EQ(ours, theirs) << "value " << i;

    Vec3 back;  // and the generated code's bytes read as the record
    ASSERT_TRUE(deserialised(record_type, theirs, back));
    EXPECT_EQ(std::memcmp(&back, &v, sizeof v), 0);
  }
}

TEST(DdsRecordWire, EveryKindOfFieldRoundTripsAndEachSampleIsSizedExactly) {
  RecordPubSubType<ProbeReading> type;
  EXPECT_EQ(std::string(type.getName()), "probe_msgs::msg::dds_::ProbeReading_");
  for (int seed = 1; seed <= 100; ++seed) {
    ProbeReading sent = test::probeReading(seed);
    const auto bytes = serialised(type, sent);
    EXPECT_EQ(bytes.size(), type.getSerializedSizeProvider(&sent)()) << "seed " << seed;
    EXPECT_LE(bytes.size(), type.m_typeSize);  // 255-character strings, 100-element sequences
    ProbeReading got;
    ASSERT_TRUE(deserialised(type, bytes, got)) << "seed " << seed;
    EXPECT_TRUE(test::same(got, sent)) << "seed " << seed;
  }
  ProbeReading empty;  // default values: empty string and sequence
  ProbeReading got = test::probeReading(3);
  ASSERT_TRUE(deserialised(type, serialised(type, empty), got));
  EXPECT_TRUE(test::same(got, empty));
}

TEST(DdsRecordWire, AStringEndsAtItsFirstNulOnTheWire) {
  // Fast CDR writes a string as a C string; the reader keeps what a sender can mean, also when a
  // peer sends bytes after a '\0' (the fuzzer's round trip found the two sides disagreeing).
  RecordPubSubType<ProbeReading> type;
  ProbeReading sent = test::probeReading(1);
  sent.label = std::string("ab\0cd", 5);
  auto bytes = serialised(type, sent);
  ProbeReading got;
  ASSERT_TRUE(deserialised(type, bytes, got));
  EXPECT_EQ(got.label, "ab");
  // The label's length, 3 ("ab\0"), made 11: eight more bytes after the '\0' (eight, so that the
  // fields after it keep their alignment).
  bytes[20] = 11;
  bytes.insert(bytes.begin() + 27, {'x', 'y', 'z', 'w', 'v', 'u', 't', 's'});
  ProbeReading odd;
  ASSERT_TRUE(deserialised(type, bytes, odd));
  EXPECT_EQ(odd.label, "ab");
  EXPECT_TRUE(test::same(odd, got));
}

// A string read leaves Fast CDR knowing a character came last, so that the field after it is
// read at its alignment: two one-letter strings then an int was read 2 bytes off.
TEST(DdsRecordWire, FieldsAfterAStringOfAnyLengthAreReadAtTheirAlignment) {
  RecordPubSubType<test::TwoLabels> type;
  std::mt19937 random(7);
  std::uniform_int_distribution<int> length(0, 9);
  for (int i = 0; i < 200; ++i) {
    test::TwoLabels sent;
    sent.first = std::string(static_cast<std::size_t>(length(random)), 'a');
    sent.second = std::string(static_cast<std::size_t>(length(random)), 'b');
    sent.count = i;
    sent.depth = 0.001 * i;
    test::TwoLabels got;
    ASSERT_TRUE(deserialised(type, serialised(type, sent), got)) << "case " << i << ": '" << sent.first << "', '"
                                                                 << sent.second << "'";
    EXPECT_EQ(got.first, sent.first);
    EXPECT_EQ(got.second, sent.second);
    EXPECT_EQ(got.count, sent.count);
    EXPECT_EQ(got.depth, sent.depth);
  }
}

TEST(DdsRecordWire, ARecordIsBoundedWhenEveryFieldIs) {
  EXPECT_TRUE(RecordPubSubType<Vec3>().is_bounded());
  EXPECT_TRUE(RecordPubSubType<Gains>().is_bounded());
  EXPECT_FALSE(RecordPubSubType<ProbeReading>().is_bounded());  // a string, a sequence, an Event
  // Bounded: the maximum is the size (double, int32, boolean, the encapsulation, padding to 4).
  Gains gains{1.0, 2, true};
  RecordPubSubType<Gains> type;
  EXPECT_EQ(type.getSerializedSizeProvider(&gains)(), 4U + 8U + 4U + 1U);
  EXPECT_EQ(type.m_typeSize, 4U + 8U + 4U + 1U + 3U);
}

TEST(DdsRecordWire, ShortAndMalformedPayloadsAreRefusedWithoutThrowing) {
  RecordPubSubType<ProbeReading> type;
  ProbeReading sent = test::probeReading(2);
  const auto good = serialised(type, sent);

  // Every truncation of a good payload (its last field, a Twist, has no optional part).
  for (std::size_t length = 0; length < good.size(); ++length) {
    ProbeReading got;
    EXPECT_FALSE(deserialised(type, {good.begin(), good.begin() + static_cast<long>(length)}, got)) << "length " << length;
  }

  const auto corrupted = [&](std::size_t at, const std::vector<unsigned char>& bytes) {
    auto bad = good;
    std::copy(bytes.begin(), bytes.end(), bad.begin() + static_cast<long>(at));
    ProbeReading got;
    return deserialised(type, bad, got);
  };
  EXPECT_FALSE(corrupted(0, {0x7f, 0x7f}));  // an unknown encapsulation
  EXPECT_FALSE(corrupted(4, {2}));           // `valid`, a boolean, is neither 0 nor 1
  EXPECT_FALSE(corrupted(20, {0xff, 0xff, 0xff, 0x7f}));  // the label's length (after the bool, padding, depth): 2 GB
  EXPECT_TRUE(corrupted(4, {1}));

  // 2,000 seeded random corruptions of 1 to 8 bytes: refused or read, never thrown or crashed.
  std::mt19937 random(7);
  int refused = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<unsigned char> bytes(1 + random() % 8);
    for (auto& b : bytes) b = static_cast<unsigned char>(random());
    const std::size_t at = random() % (good.size() - bytes.size());
    refused += corrupted(at, bytes) ? 0 : 1;
  }
  EXPECT_GT(refused, 0);
}

TEST(DdsRecordWire, SerialisingAllocatesOnlyWhatTheMessageNeeds) {
  RecordPubSubType<ProbeReading> type;
  ProbeReading sent = test::probeReading(4);  // a long label, a sequence, an Event of short strings
  SerializedPayload_t payload(type.m_typeSize);
  const long serialising = test_support::allocationsDuring([&] {
    payload.length = 0;
    std::uint32_t size = type.getSerializedSizeProvider(&sent)();
    EXPECT_LE(size, payload.max_size);
    EXPECT_TRUE(type.serialize(&sent, &payload));
  });
  EXPECT_EQ(serialising, 0);  // into Fast DDS's payload; the Event's message keeps its strings short

  // Reading into a value whose string and sequence already have the room: nothing either.
  ProbeReading got = test::probeReading(4);
  const long reading = test_support::allocationsDuring([&] { EXPECT_TRUE(type.deserialize(&payload, &got)); });
  EXPECT_EQ(reading, 0);
  EXPECT_TRUE(test::same(got, sent));
}

}  // namespace
}  // namespace cobra::dds
