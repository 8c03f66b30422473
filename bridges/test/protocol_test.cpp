// The I-SUR (UDP) and Omni (TCP) codecs: round trips, the documented byte layout, and one test
// per rejection reason.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "cobra/bridges/isur_protocol.hpp"
#include "cobra/bridges/omni_protocol.hpp"

namespace cobra::bridges {
namespace {

using wire::DecodeStatus;

isur::State sampleState(std::uint16_t n) {
  isur::State s;
  s.joint_count = n;
  s.flags = isur::kPoseValid;
  for (std::uint16_t i = 0; i < n; ++i) s.joints[i] = 0.1 * (i + 1);
  s.pose.position = {0.1, -0.2, 0.3};
  s.pose.quaternion = {0.0, 0.0, std::sin(0.25), std::cos(0.25)};
  s.wrench = {1, 2, 3, 0.1, 0.2, 0.3};
  return s;
}

std::vector<std::uint8_t> encoded(const isur::State& s, std::uint32_t seq = 1) {
  std::vector<std::uint8_t> out(isur::kMaxFrameSize);
  out.resize(isur::encode(s, {seq, 123}, out));
  return out;
}

// Rewrites the CRC after a deliberate change, so the decoder reaches the field checks.
void fixCrc(std::vector<std::uint8_t>& bytes) {
  const std::uint32_t crc = wire::crc32(std::span(bytes).first(bytes.size() - 4));
  for (std::size_t i = 0; i < 4; ++i) bytes[bytes.size() - 4 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
}

void putF64(std::vector<std::uint8_t>& bytes, std::size_t offset, double v) {
  const auto bits = std::bit_cast<std::uint64_t>(v);
  for (int i = 0; i < 8; ++i) bytes[offset + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(bits >> (8 * i));
}

TEST(IsurProtocol, StateRoundTripsWithTheDocumentedLayout) {
  const isur::State s = sampleState(8);
  const auto bytes = encoded(s, 0x01020304);
  ASSERT_EQ(bytes.size(), 24U + 112 + 8 * 8 + 4);
  EXPECT_EQ(bytes[0], 'I');
  EXPECT_EQ(bytes[3], 'R');
  EXPECT_EQ(bytes[4], 1);   // version, little-endian
  EXPECT_EQ(bytes[6], 3);   // type State
  EXPECT_EQ(bytes[8], 4);   // sequence 0x01020304, low byte first
  EXPECT_EQ(bytes[11], 1);
  EXPECT_EQ(bytes[20], 112 + 64);  // payload length
  EXPECT_EQ(bytes[24], 8);         // joint count
  EXPECT_EQ(bytes[26], isur::kPoseValid);
  isur::State d;
  wire::FrameHeader h;
  ASSERT_EQ(isur::decode(bytes, d, h), DecodeStatus::Ok);
  EXPECT_EQ(h.sequence, 0x01020304U);
  EXPECT_EQ(d.joint_count, 8);
  EXPECT_EQ(d.joints, s.joints);
  EXPECT_EQ(d.pose.position, s.pose.position);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(d.pose.quaternion[i], s.pose.quaternion[i], 1e-15);
  EXPECT_EQ(d.wrench, s.wrench);
  // Every documented flag travels: bit 3, a Cartesian command held by the continuity rule.
  isur::State held = s;
  held.flags = isur::kPoseValid | isur::kCartesianHeld | isur::kCartesianDiscontinuous;
  const auto held_bytes = encoded(held);
  EXPECT_EQ(held_bytes[26], 0x0E);
  ASSERT_EQ(isur::decode(held_bytes, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.flags, held.flags);
}

TEST(IsurProtocol, CommandsRoundTripAndAreNotStates) {
  isur::Command joints;
  joints.joint_count = 3;
  joints.joints = {0.5, -0.5, 0.25};
  std::vector<std::uint8_t> out(isur::kMaxFrameSize);
  out.resize(isur::encode(joints, {7, 8}, out));
  ASSERT_EQ(out.size(), 24U + 8 + 24 + 4);
  isur::Command d;
  wire::FrameHeader h;
  ASSERT_EQ(isur::decode(out, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.type, isur::MessageType::JointCommand);
  EXPECT_EQ(d.joint_count, 3);
  EXPECT_EQ(d.joints[2], 0.25);
  isur::State not_a_state;
  EXPECT_EQ(isur::decode(out, not_a_state, h), DecodeStatus::BadType);

  isur::Command pose;
  pose.type = isur::MessageType::CartesianCommand;
  pose.pose.position = {1, 2, 3};
  out.assign(isur::kMaxFrameSize, 0);
  out.resize(isur::encode(pose, {9, 10}, out));
  ASSERT_EQ(isur::decode(out, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.type, isur::MessageType::CartesianCommand);
  EXPECT_EQ(d.pose.position[2], 3.0);
  isur::Command bad;
  bad.joint_count = 0;
  EXPECT_EQ(isur::encode(bad, {}, out), 0U);
  bad.joint_count = 17;
  EXPECT_EQ(isur::encode(bad, {}, out), 0U);
}

TEST(IsurProtocol, RejectsEachKindOfMalformedState) {
  const auto good = encoded(sampleState(8));
  isur::State d;
  wire::FrameHeader h;
  auto check = [&](std::vector<std::uint8_t> bytes, DecodeStatus expected, const char* what) {
    const isur::State before = d;
    EXPECT_EQ(isur::decode(bytes, d, h), expected) << what;
    EXPECT_EQ(d.joints, before.joints) << what << ": output written on failure";
  };
  check(std::vector<std::uint8_t>(good.begin(), good.begin() + 10), DecodeStatus::Truncated, "header cut");
  check(std::vector<std::uint8_t>(good.begin(), good.end() - 1), DecodeStatus::Truncated, "CRC cut");
  auto b = good;
  b[0] = 'X';
  check(b, DecodeStatus::BadMagic, "magic");
  b = good;
  b[4] = 2;
  check(b, DecodeStatus::BadVersion, "version");
  b = good;
  b[40] ^= 0xFF;
  check(b, DecodeStatus::BadCrc, "payload bit flip");
  b = good;
  b[6] = 9;
  fixCrc(b);
  check(b, DecodeStatus::BadType, "type");
  b = good;
  b[24] = 7;  // says 7 joints, payload sized for 8
  fixCrc(b);
  check(b, DecodeStatus::BadLength, "joint count vs length");
  b = good;
  b[24] = 0;
  fixCrc(b);
  check(b, DecodeStatus::BadLength, "zero joints");
  b = good;
  putF64(b, 32 + 8 * 3, std::numeric_limits<double>::quiet_NaN());
  fixCrc(b);
  check(b, DecodeStatus::NonFinite, "NaN joint");
  b = good;
  putF64(b, 32 + 64 + 24 + 32 + 8, std::numeric_limits<double>::infinity());  // wrench fy
  fixCrc(b);
  check(b, DecodeStatus::NonFinite, "infinite wrench");
  b = good;
  putF64(b, 32 + 64 + 24 + 24, 2.0);  // qw: |q| != 1
  fixCrc(b);
  check(b, DecodeStatus::BadValue, "non-unit quaternion");
  b = good;
  b[26] |= 0x80;  // unknown flag bit
  fixCrc(b);
  check(b, DecodeStatus::BadValue, "flags");
  b = good;
  b.push_back(0);
  check(b, DecodeStatus::BadLength, "trailing byte");
}

// Seeded random byte strings and random mutations of a valid frame: never Ok by accident, never crash.
TEST(IsurProtocol, RandomBytesAndMutationsAreRejected) {
  std::mt19937_64 rng(8);
  const auto good = encoded(sampleState(8));
  isur::State d;
  wire::FrameHeader h;
  int rejected = 0;
  for (int i = 0; i < 2000; ++i) {  // 2000 cases: half random, half mutated
    std::vector<std::uint8_t> b;
    if (i % 2 == 0) {
      b.resize(rng() % (isur::kMaxFrameSize + 8));
      for (auto& x : b) x = static_cast<std::uint8_t>(rng());
    } else {
      b = good;
      b[rng() % b.size()] ^= static_cast<std::uint8_t>(1U << (rng() % 8));
    }
    rejected += isur::decode(b, d, h) != DecodeStatus::Ok;
  }
  EXPECT_EQ(rejected, 2000);
}

TEST(OmniProtocol, StateAndWrenchRoundTripAndRejectBadFields) {
  omni::State s;
  s.position = {0.01, 0.02, -0.03};
  s.twist = {0.1, 0.2, 0.3, 0, 0, 0};
  s.buttons = 2;
  std::vector<std::uint8_t> out(omni::kMaxFrameSize);
  out.resize(omni::encode(s, {5, 6}, out));
  ASSERT_EQ(out.size(), 24U + 112 + 4);
  EXPECT_EQ(out[0], 'O');
  EXPECT_EQ(out[3], 'I');
  omni::State d;
  wire::FrameHeader h;
  ASSERT_EQ(omni::decode(out, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.position, s.position);
  EXPECT_EQ(d.twist, s.twist);
  EXPECT_EQ(d.buttons, 2U);
  omni::WrenchCommand not_a_wrench;
  EXPECT_EQ(omni::decode(out, not_a_wrench, h), DecodeStatus::BadType);

  auto b = out;
  b[24 + 104] = 0x04;  // unknown button bit
  fixCrc(b);
  EXPECT_EQ(omni::decode(b, d, h), DecodeStatus::BadValue);
  b = out;
  putF64(b, 24 + 56, std::numeric_limits<double>::quiet_NaN());  // vx
  fixCrc(b);
  EXPECT_EQ(omni::decode(b, d, h), DecodeStatus::NonFinite);
  b = out;
  b[30] ^= 1;
  EXPECT_EQ(omni::decode(b, d, h), DecodeStatus::BadCrc);
  EXPECT_EQ(omni::decode(std::span(out).first(50), d, h), DecodeStatus::Truncated);

  omni::WrenchCommand w{{1, -2, 3, 0, 0, 0}};
  out.assign(omni::kMaxFrameSize, 0);
  out.resize(omni::encode(w, {1, 2}, out));
  ASSERT_EQ(out.size(), 24U + 48 + 4);
  omni::WrenchCommand wd;
  ASSERT_EQ(omni::decode(out, wd, h), DecodeStatus::Ok);
  EXPECT_EQ(wd.wrench, w.wrench);
}

}  // namespace
}  // namespace cobra::bridges
