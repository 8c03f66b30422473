// The byte-level layer: CRC-32 against its published check value, little-endian layout, frame
// checks, and the lateness filter's sequence and delay rules.
#include "cobra/bridges/wire.hpp"

#include <gtest/gtest.h>

#include <string_view>
#include <vector>

namespace cobra::bridges::wire {
namespace {

TEST(Crc32, MatchesTheStandardCheckValue) {
  constexpr std::string_view check = "123456789";  // CRC-32/ISO-HDLC check value 0xCBF43926
  const std::vector<std::uint8_t> bytes(check.begin(), check.end());
  EXPECT_EQ(crc32(bytes), 0xCBF43926U);
  EXPECT_EQ(crc32({}), 0U);
}

TEST(Wire, WritesLittleEndianFieldsByteByByte) {
  std::array<std::uint8_t, 16> out{};
  Writer w(out);
  w.u16(0x0102);
  w.u32(0x03040506);
  w.f64(1.0);  // IEEE 754: 0x3FF0000000000000
  ASSERT_TRUE(w.ok());
  const std::array<std::uint8_t, 14> expected = {0x02, 0x01, 0x06, 0x05, 0x04, 0x03, 0, 0, 0, 0, 0, 0, 0xF0, 0x3F};
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), out.begin()));
  w.u32(0);  // 14 + 4 > 16
  EXPECT_FALSE(w.ok());
  Reader r(std::span<const std::uint8_t>(out.data(), 14));
  EXPECT_EQ(r.u16(), 0x0102);
  EXPECT_EQ(r.u32(), 0x03040506U);
  EXPECT_EQ(r.f64(), 1.0);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.u16(), 0);
  EXPECT_FALSE(r.ok());
}

std::vector<std::uint8_t> frame(std::uint32_t payload_bytes) {
  std::vector<std::uint8_t> out(64);
  const FrameHeader h{0xAABBCCDD, 3, 7, 42, 1000, 0};
  const std::size_t n = writeFrame(out, h, [&](Writer& w) {
    for (std::uint32_t i = 0; i < payload_bytes; ++i) w.u16(static_cast<std::uint16_t>(i));
  });
  out.resize(n);
  return out;
}

TEST(Wire, ChecksEveryPartOfAFrame) {
  auto bytes = frame(4);  // 8 payload bytes
  ASSERT_EQ(bytes.size(), kHeaderSize + 8 + kTrailerSize);
  FrameHeader h;
  std::span<const std::uint8_t> payload;
  ASSERT_EQ(checkFrame(bytes, 0xAABBCCDD, 3, 64, h, payload), DecodeStatus::Ok);
  EXPECT_EQ(h.type, 7);
  EXPECT_EQ(h.sequence, 42U);
  EXPECT_EQ(h.timestamp_ns, 1000U);
  EXPECT_EQ(payload.size(), 8U);
  EXPECT_EQ(checkFrame(bytes, 0x11223344, 3, 64, h, payload), DecodeStatus::BadMagic);
  EXPECT_EQ(checkFrame(bytes, 0xAABBCCDD, 4, 64, h, payload), DecodeStatus::BadVersion);
  EXPECT_EQ(checkFrame(bytes, 0xAABBCCDD, 3, 7, h, payload), DecodeStatus::BadLength);
  EXPECT_EQ(checkFrame(std::span(bytes).first(bytes.size() - 1), 0xAABBCCDD, 3, 64, h, payload),
            DecodeStatus::Truncated);
  EXPECT_EQ(checkFrame(std::span(bytes).first(10), 0xAABBCCDD, 3, 64, h, payload), DecodeStatus::Truncated);
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_EQ(checkFrame(longer, 0xAABBCCDD, 3, 64, h, payload), DecodeStatus::BadLength);
  for (std::size_t i = 0; i < bytes.size(); ++i) {  // any single flipped bit past the checked header fields
    if (i < 8 || (i >= 20 && i < 24)) continue;
    auto corrupted = bytes;
    corrupted[i] ^= 0x10;
    EXPECT_EQ(checkFrame(corrupted, 0xAABBCCDD, 3, 64, h, payload), DecodeStatus::BadCrc) << "byte " << i;
  }
}

TEST(LatenessFilter, RejectsOldSequencesAndDelayedTimestampsAcrossClockOffsets) {
  LatenessFilter filter(5'000'000);  // 5 ms
  const std::int64_t offset = 1'000'000'000'000;  // receiver clock ahead of the sender's by 1000 s
  EXPECT_EQ(filter.accept(10, 100'000'000, 100'000'000 + offset), DecodeStatus::Ok);
  EXPECT_EQ(filter.accept(10, 101'000'000, 101'000'000 + offset), DecodeStatus::Late);  // duplicate
  EXPECT_EQ(filter.accept(9, 102'000'000, 102'000'000 + offset), DecodeStatus::Late);   // older
  EXPECT_EQ(filter.accept(11, 103'000'000, 104'000'000 + offset), DecodeStatus::Ok);    // 1 ms transit
  // Sent at 104 ms, arrives 10 ms later: 10 ms over the fastest transit seen, over the 5 ms allowed.
  EXPECT_EQ(filter.accept(12, 104'000'000, 114'000'000 + offset), DecodeStatus::Delayed);
  EXPECT_EQ(filter.accept(13, 115'000'000, 117'000'000 + offset), DecodeStatus::Ok);
  // Sequence numbers wrap: 0xFFFFFFFF then 0 is newer.
  LatenessFilter wrap;
  EXPECT_EQ(wrap.accept(0xFFFFFFFFU, 0, 0), DecodeStatus::Ok);
  EXPECT_EQ(wrap.accept(0, 1, 1), DecodeStatus::Ok);
  EXPECT_EQ(wrap.accept(0xFFFFFFFFU, 2, 2), DecodeStatus::Late);
  wrap.reset();
  EXPECT_EQ(wrap.accept(5, 3, 3), DecodeStatus::Ok);
}

TEST(DecodeStatus, NamesRoundTrip) {
  for (std::size_t i = 0; i < kDecodeStatusCount; ++i) {
    const auto status = static_cast<DecodeStatus>(i);
    DecodeStatus parsed;
    ASSERT_TRUE(parseDecodeStatus(toString(status), parsed));
    EXPECT_EQ(parsed, status);
  }
  DecodeStatus parsed;
  EXPECT_FALSE(parseDecodeStatus("bogus", parsed));
}

}  // namespace
}  // namespace cobra::bridges::wire
