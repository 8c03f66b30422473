// The I-SUR (UDP) and Omni (TCP) codecs: round trips, the documented byte layout, and one test
// per rejection reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "cobra/bridges/isur_protocol.hpp"
#include "cobra/bridges/omni_protocol.hpp"

namespace cobra::bridges {
namespace {

using wire::DecodeStatus;

isur::State sampleState(std::uint16_t n, std::uint16_t tools = 1) {
  isur::State s;
  s.joint_count = n;
  s.tool_count = tools;
  s.flags = isur::kPoseValid;
  for (std::uint16_t i = 0; i < n; ++i) s.joints[i] = 0.1 * (i + 1);
  for (std::size_t t = 0; t < tools; ++t) {
    const double k = static_cast<double>(t + 1);
    s.tools[t].pose.position = {0.1 * k, -0.2, 0.3};
    s.tools[t].pose.quaternion = {0.0, 0.0, std::sin(0.25 * k), std::cos(0.25 * k)};
    s.tools[t].wrench = {1 * k, 2, 3, 0.1, 0.2, 0.3 * k};
  }
  return s;
}

std::vector<std::uint8_t> encoded(const isur::State& s, std::uint32_t seq = 1) {
  std::vector<std::uint8_t> out(isur::kMaxFrameSize);
  out.resize(isur::encode(s, {seq, 123}, out));
  return out;
}

std::vector<std::uint8_t> encoded(const isur::Command& c, std::uint32_t seq = 1) {
  std::vector<std::uint8_t> out(isur::kMaxFrameSize);
  out.resize(isur::encode(c, {seq, 123}, out));
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

void expectSameTool(const isur::ToolState& a, const isur::ToolState& b) {
  EXPECT_EQ(a.pose.position, b.pose.position);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(a.pose.quaternion[i], b.pose.quaternion[i], 1e-15);
  EXPECT_EQ(a.wrench, b.wrench);
}

// Byte offsets in a one-tool State frame with 8 joints: header 24, prefix 16, joints 64, then
// the tool: position 104, quaternion 128 (qw 152), wrench 160.
constexpr std::size_t kJoints8 = 40;
constexpr std::size_t kTool0 = kJoints8 + 64;

TEST(IsurProtocol, StateRoundTripsWithTheDocumentedLayout) {
  const isur::State s = sampleState(8);
  const auto bytes = encoded(s, 0x01020304);
  ASSERT_EQ(bytes.size(), 24U + 16 + 8 * 8 + 104 + 4);
  EXPECT_EQ(bytes[0], 'I');
  EXPECT_EQ(bytes[3], 'R');
  EXPECT_EQ(bytes[4], 2);   // version, little-endian
  EXPECT_EQ(bytes[6], 3);   // type State
  EXPECT_EQ(bytes[8], 4);   // sequence 0x01020304, low byte first
  EXPECT_EQ(bytes[11], 1);
  EXPECT_EQ(bytes[20], 16 + 64 + 104);  // payload length
  EXPECT_EQ(bytes[24], 8);              // joint count
  EXPECT_EQ(bytes[26], isur::kPoseValid);
  EXPECT_EQ(bytes[28], 1);  // tool count
  isur::State d;
  wire::FrameHeader h;
  ASSERT_EQ(isur::decode(bytes, d, h), DecodeStatus::Ok);
  EXPECT_EQ(h.sequence, 0x01020304U);
  EXPECT_EQ(d.joint_count, 8);
  EXPECT_EQ(d.tool_count, 1);
  EXPECT_EQ(d.joints, s.joints);
  expectSameTool(d.tools[0], s.tools[0]);
  // Every documented flag travels: bit 3, a Cartesian command held by the continuity rule.
  isur::State held = s;
  held.flags = isur::kPoseValid | isur::kCartesianHeld | isur::kCartesianDiscontinuous;
  const auto held_bytes = encoded(held);
  EXPECT_EQ(held_bytes[26], 0x0E);
  ASSERT_EQ(isur::decode(held_bytes, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.flags, held.flags);
}

TEST(IsurProtocol, TwoToolStateCarriesBothPosesBothWrenchesAndTheActuationFields) {
  isur::State s = sampleState(14, 2);
  s.flags = isur::kPoseValid | isur::kWrenchSaturatedTool1 | isur::kActuating | isur::kActuationRefused;
  s.actuations = 0x0A0B0C0D;
  s.actuation_request = 7;
  const auto bytes = encoded(s);
  ASSERT_EQ(bytes.size(), 24U + 16 + 8 * 14 + 2 * 104 + 4);
  EXPECT_EQ(bytes[28], 2);     // tool count
  EXPECT_EQ(bytes[26], 0x72);  // flags
  EXPECT_EQ(bytes[32], 0x0D);  // actuations, low byte first
  EXPECT_EQ(bytes[35], 0x0A);
  EXPECT_EQ(bytes[36], 7);  // acknowledged request
  isur::State d;
  wire::FrameHeader h;
  ASSERT_EQ(isur::decode(bytes, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.joint_count, 14);
  EXPECT_EQ(d.tool_count, 2);
  EXPECT_EQ(d.flags, s.flags);
  EXPECT_EQ(d.actuations, s.actuations);
  EXPECT_EQ(d.actuation_request, 7U);
  EXPECT_EQ(d.joints, s.joints);
  expectSameTool(d.tools[0], s.tools[0]);
  expectSameTool(d.tools[1], s.tools[1]);
  // Tool 1's wrench fz sits after the joints, tool 0 (104 bytes) and tool 1's pose (56 bytes).
  double fz = 0.0;
  std::uint64_t bits = 0;
  constexpr std::size_t kTool1Fz = 40 + 112 + 104 + 56 + 16;
  for (std::size_t i = 0; i < 8; ++i) bits |= std::uint64_t{bytes[kTool1Fz + i]} << (8 * i);
  std::memcpy(&fz, &bits, 8);
  EXPECT_EQ(fz, s.tools[1].wrench[2]);
}

TEST(IsurProtocol, CommandsRoundTripAndAreNotStates) {
  isur::Command joints;
  joints.joint_count = 3;
  joints.joints = {0.5, -0.5, 0.25};
  std::vector<std::uint8_t> out = encoded(joints, 7);
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
  pose.poses[0].position = {1, 2, 3};
  out = encoded(pose, 9);
  ASSERT_EQ(out.size(), 24U + 8 + 56 + 4);
  ASSERT_EQ(isur::decode(out, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.type, isur::MessageType::CartesianCommand);
  EXPECT_EQ(d.tool_count, 1);
  EXPECT_EQ(d.tool_mask, 1);
  EXPECT_EQ(d.poses[0].position[2], 3.0);
  isur::Command bad;
  bad.joint_count = 0;
  EXPECT_EQ(isur::encode(bad, {}, out), 0U);
  bad.joint_count = 17;
  EXPECT_EQ(isur::encode(bad, {}, out), 0U);
}

TEST(IsurProtocol, TwoToolCartesianCommandCarriesOnePosePerToolAndTheMask) {
  isur::Command c;
  c.type = isur::MessageType::CartesianCommand;
  c.tool_count = 2;
  c.tool_mask = 0b10;  // only the left tool has a new target
  c.poses[0].position = {0.1, 0.2, 0.3};
  c.poses[1].position = {-0.1, -0.2, -0.3};
  c.poses[1].quaternion = {std::sin(0.5), 0.0, 0.0, std::cos(0.5)};
  const auto out = encoded(c);
  ASSERT_EQ(out.size(), 24U + 8 + 2 * 56 + 4);
  EXPECT_EQ(out[24], 2);  // tool count
  EXPECT_EQ(out[26], 2);  // mask
  isur::Command d;
  wire::FrameHeader h;
  ASSERT_EQ(isur::decode(out, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.tool_count, 2);
  EXPECT_EQ(d.tool_mask, 0b10);
  EXPECT_EQ(d.poses[0].position, c.poses[0].position);
  EXPECT_EQ(d.poses[1].position, c.poses[1].position);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(d.poses[1].quaternion[i], c.poses[1].quaternion[i], 1e-15);
  isur::Command bad = c;
  for (const int tools : {0, 3}) {
    bad.tool_count = static_cast<std::uint16_t>(tools);
    std::vector<std::uint8_t> buffer(isur::kMaxFrameSize);
    EXPECT_EQ(isur::encode(bad, {}, buffer), 0U) << tools << " tools";
  }
  bad = c;
  for (const int mask : {0, 0b100}) {
    bad.tool_mask = static_cast<std::uint16_t>(mask);
    std::vector<std::uint8_t> buffer(isur::kMaxFrameSize);
    EXPECT_EQ(isur::encode(bad, {}, buffer), 0U) << "mask " << mask;
  }
}

TEST(IsurProtocol, ToolActuationRoundTripsAndRejectsARequestOfZeroOrAnUnknownTool) {
  isur::Command c;
  c.type = isur::MessageType::ToolActuation;
  c.actuation = {.tool = 0, .request = 0x01020304};
  auto out = encoded(c);
  ASSERT_EQ(out.size(), 24U + 8 + 4);
  EXPECT_EQ(out[6], 4);  // type ToolActuation
  EXPECT_EQ(out[28], 0x04);
  isur::Command d;
  wire::FrameHeader h;
  ASSERT_EQ(isur::decode(out, d, h), DecodeStatus::Ok);
  EXPECT_EQ(d.type, isur::MessageType::ToolActuation);
  EXPECT_EQ(d.actuation.tool, 0);
  EXPECT_EQ(d.actuation.request, 0x01020304U);
  isur::State not_a_state;
  EXPECT_EQ(isur::decode(out, not_a_state, h), DecodeStatus::BadType);

  auto b = out;
  b[24] = 2;  // tool 2 of at most 2
  fixCrc(b);
  EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::BadValue);
  b = out;
  for (std::size_t i = 28; i < 32; ++i) b[i] = 0;  // request 0
  fixCrc(b);
  EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::BadValue);
  b = out;
  b[26] = 1;  // reserved
  fixCrc(b);
  EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::BadValue);
  EXPECT_EQ(isur::decode(std::span(out).first(out.size() - 2), d, h), DecodeStatus::Truncated);
  std::vector<std::uint8_t> buffer(isur::kMaxFrameSize);
  c.actuation.request = 0;
  EXPECT_EQ(isur::encode(c, {}, buffer), 0U);
  c.actuation = {.tool = 2, .request = 1};
  EXPECT_EQ(isur::encode(c, {}, buffer), 0U);
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
  b[4] = 1;
  check(b, DecodeStatus::BadVersion, "version 1 (one tool, no actuation): not accepted");
  b = good;
  b[4] = 3;
  check(b, DecodeStatus::BadVersion, "version 3");
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
  putF64(b, kJoints8 + 8 * 3, std::numeric_limits<double>::quiet_NaN());
  fixCrc(b);
  check(b, DecodeStatus::NonFinite, "NaN joint");
  b = good;
  putF64(b, kTool0 + 56 + 8, std::numeric_limits<double>::infinity());  // wrench fy
  fixCrc(b);
  check(b, DecodeStatus::NonFinite, "infinite wrench");
  b = good;
  putF64(b, kTool0 + 24 + 24, 2.0);  // qw: |q| != 1
  fixCrc(b);
  check(b, DecodeStatus::BadValue, "non-unit quaternion");
  b = good;
  b[26] |= 0x80;  // unknown flag bit
  fixCrc(b);
  check(b, DecodeStatus::BadValue, "flags");
  b = good;
  b[26] |= isur::kWrenchSaturatedTool1;  // a second tool's flag on a one-tool robot
  fixCrc(b);
  check(b, DecodeStatus::BadValue, "tool 1 flag with one tool");
  b = good;
  b[30] = 1;  // reserved
  fixCrc(b);
  check(b, DecodeStatus::BadValue, "reserved");
  b = good;
  b.push_back(0);
  check(b, DecodeStatus::BadLength, "trailing byte");
}

TEST(IsurProtocol, RejectsBadToolCountsAndABadQuaternionOfEitherTool) {
  const auto good = encoded(sampleState(14, 2));
  const std::size_t tool0 = 40 + 8 * 14, tool1 = tool0 + 104;
  isur::State d;
  wire::FrameHeader h;
  for (const int tools : {0, 3, 255}) {
    auto b = good;
    b[28] = static_cast<std::uint8_t>(tools);
    fixCrc(b);
    EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::BadValue) << tools << " tools";
  }
  auto b = good;
  b[28] = 1;  // one tool, but the payload holds two
  fixCrc(b);
  EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::BadLength);
  for (const std::size_t tool : {tool0, tool1}) {
    b = good;
    putF64(b, tool + 24, 0.5);  // qx: |q| != 1
    fixCrc(b);
    EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::BadValue) << "quaternion at " << tool;
    b = good;
    putF64(b, tool + 56 + 40, std::numeric_limits<double>::quiet_NaN());  // tz
    fixCrc(b);
    EXPECT_EQ(isur::decode(b, d, h), DecodeStatus::NonFinite) << "wrench at " << tool;
  }
  for (const std::size_t cut : {std::size_t{30}, tool1, good.size() - 1}) {
    EXPECT_EQ(isur::decode(std::span(good).first(cut), d, h), DecodeStatus::Truncated) << "cut at " << cut;
  }
  // A Cartesian command: tool count, mask and each tool's quaternion are checked.
  isur::Command c;
  c.type = isur::MessageType::CartesianCommand;
  c.tool_count = 2;
  c.tool_mask = 0b01;
  const auto command = encoded(c);
  isur::Command dc;
  for (const int tools : {0, 3}) {
    b = command;
    b[24] = static_cast<std::uint8_t>(tools);
    fixCrc(b);
    EXPECT_EQ(isur::decode(b, dc, h), DecodeStatus::BadValue) << tools << " tools";
  }
  for (const int mask : {0, 0b100}) {
    b = command;
    b[26] = static_cast<std::uint8_t>(mask);
    fixCrc(b);
    EXPECT_EQ(isur::decode(b, dc, h), DecodeStatus::BadValue) << "mask " << mask;
  }
  b = command;
  putF64(b, 32 + 56 + 48, 0.9);  // tool 1's qw, although tool 1 is not in the mask
  fixCrc(b);
  EXPECT_EQ(isur::decode(b, dc, h), DecodeStatus::BadValue);
  EXPECT_EQ(isur::decode(std::span(command).first(command.size() - 60), dc, h), DecodeStatus::Truncated);
}

// Seeded random byte strings and random mutations of valid frames: never Ok by accident, never crash.
TEST(IsurProtocol, RandomBytesAndMutationsAreRejected) {
  std::mt19937_64 rng(8);
  const std::vector<std::vector<std::uint8_t>> goods = {encoded(sampleState(8)), encoded(sampleState(14, 2))};
  isur::State d;
  wire::FrameHeader h;
  int rejected = 0;
  for (int i = 0; i < 3000; ++i) {  // 3000 cases: a third random, a third mutated of each valid frame
    std::vector<std::uint8_t> b;
    if (i % 3 == 0) {
      b.resize(rng() % (isur::kMaxFrameSize + 8));
      for (auto& x : b) x = static_cast<std::uint8_t>(rng());
    } else {
      b = goods[static_cast<std::size_t>(i % 3 - 1)];
      b[rng() % b.size()] ^= static_cast<std::uint8_t>(1U << (rng() % 8));
    }
    rejected += isur::decode(b, d, h) != DecodeStatus::Ok;
  }
  EXPECT_EQ(rejected, 3000);
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
