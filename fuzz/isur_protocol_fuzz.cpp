// libFuzzer target: the I-SUR UDP decoders (commands: joints, Cartesian poses for 1..kMaxTools
// tools, tool actuations; states with 1..kMaxTools tools) on arbitrary datagrams, as they come and
// with their CRC trailer made correct; and valid messages made of the input's bytes, which must
// come back from encode + decode unchanged. A decoded message
// must satisfy the documented ranges and re-encode to the same bytes, except for the quaternions,
// which the decoder normalises (the same length, and a decode of the re-encoding gives the same
// message).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>

#include "cobra/bridges/isur_protocol.hpp"

namespace {

using namespace cobra::bridges;

void checkState(const isur::State& state, std::size_t size, const wire::FrameHeader& header) {
  if (state.joint_count < 1 || state.joint_count > isur::kMaxJoints) std::abort();
  if (state.tool_count < 1 || state.tool_count > isur::kMaxTools) std::abort();
  if ((state.flags & ~isur::kKnownStateFlags) != 0) std::abort();
  std::uint8_t out[isur::kMaxFrameSize];
  const std::size_t n = isur::encode(state, {header.sequence, header.timestamp_ns}, out);
  if (n != size) std::abort();
  isur::State again;
  wire::FrameHeader h;
  if (isur::decode(std::span<const std::uint8_t>(out, n), again, h) != wire::DecodeStatus::Ok) std::abort();
  if (again.joints != state.joints || again.actuations != state.actuations ||
      again.actuation_request != state.actuation_request || again.flags != state.flags)
    std::abort();
}

void checkCommand(const isur::Command& command, std::size_t size, const wire::FrameHeader& header) {
  if (command.type == isur::MessageType::CartesianCommand &&
      (command.tool_count < 1 || command.tool_count > isur::kMaxTools || command.tool_mask == 0 ||
       (command.tool_mask >> command.tool_count) != 0))
    std::abort();
  if (command.type == isur::MessageType::ToolActuation &&
      (command.actuation.request == 0 || command.actuation.tool >= isur::kMaxTools))
    std::abort();
  std::uint8_t out[isur::kMaxFrameSize];
  const std::size_t n = isur::encode(command, {header.sequence, header.timestamp_ns}, out);
  if (n != size) std::abort();
  isur::Command again;
  wire::FrameHeader h;
  if (isur::decode(std::span<const std::uint8_t>(out, n), again, h) != wire::DecodeStatus::Ok) std::abort();
  if (again.type != command.type) std::abort();
}

void decodeBoth(std::span<const std::uint8_t> bytes) {
  wire::FrameHeader header;
  isur::State state;
  if (isur::decode(bytes, state, header) == wire::DecodeStatus::Ok) checkState(state, bytes.size(), header);
  isur::Command command;
  if (isur::decode(bytes, command, header) == wire::DecodeStatus::Ok) checkCommand(command, bytes.size(), header);
}

/// Values taken from the input in order (0 once it is used up).
class Fields {
 public:
  Fields(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t{byte()} << (8 * i);
    return v;
  }
  /// A finite double (a non-finite bit pattern becomes 0).
  double finite() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits |= std::uint64_t{byte()} << (8 * i);
    double v = 0.0;
    std::memcpy(&v, &bits, 8);
    return std::isfinite(v) ? v : 0.0;
  }
  isur::Pose pose() {
    isur::Pose p;
    for (double& v : p.position) v = finite();
    double q[4], norm = 0.0;
    for (double& v : q) {
      v = std::fmod(finite(), 1e6);  // bounded, so that the norm is finite
      norm += v * v;
    }
    norm = std::sqrt(norm);
    if (norm > 1e-3)
      for (std::size_t i = 0; i < 4; ++i) p.quaternion[i] = q[i] / norm;
    return p;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

bool samePose(const isur::Pose& a, const isur::Pose& b) {
  for (std::size_t i = 0; i < 4; ++i)
    if (std::abs(a.quaternion[i] - b.quaternion[i]) > 1e-12) return false;
  return a.position == b.position;
}

/// A valid message made of the input's bytes encodes, decodes Ok and comes back equal (the
/// quaternions to rounding): the decoders' accepting paths, which raw bytes rarely reach.
void roundTrip(const std::uint8_t* data, std::size_t size) {
  Fields f(data, size);
  std::uint8_t out[isur::kMaxFrameSize];
  wire::FrameHeader h;
  isur::State s;
  s.joint_count = static_cast<std::uint16_t>(1 + f.byte() % isur::kMaxJoints);
  s.tool_count = static_cast<std::uint16_t>(1 + f.byte() % isur::kMaxTools);
  s.flags = static_cast<std::uint16_t>(f.byte() & isur::kKnownStateFlags);
  if (s.tool_count == 1) s.flags = static_cast<std::uint16_t>(s.flags & ~isur::kWrenchSaturatedTool1);
  s.actuations = f.u32();
  s.actuation_request = f.u32();
  for (std::size_t i = 0; i < s.joint_count; ++i) s.joints[i] = f.finite();
  for (std::size_t t = 0; t < s.tool_count; ++t) {
    s.tools[t].pose = f.pose();
    for (double& v : s.tools[t].wrench) v = f.finite();
  }
  std::size_t n = isur::encode(s, {f.u32(), 0}, out);
  isur::State d;
  if (n == 0 || isur::decode(std::span<const std::uint8_t>(out, n), d, h) != wire::DecodeStatus::Ok) std::abort();
  if (d.joint_count != s.joint_count || d.tool_count != s.tool_count || d.flags != s.flags ||
      d.actuations != s.actuations || d.actuation_request != s.actuation_request || d.joints != s.joints)
    std::abort();
  for (std::size_t t = 0; t < s.tool_count; ++t)
    if (!samePose(d.tools[t].pose, s.tools[t].pose) || d.tools[t].wrench != s.tools[t].wrench) std::abort();

  isur::Command c;
  switch (f.byte() % 3) {
    case 0:
      c.type = isur::MessageType::JointCommand;
      c.joint_count = static_cast<std::uint16_t>(1 + f.byte() % isur::kMaxJoints);
      for (std::size_t i = 0; i < c.joint_count; ++i) c.joints[i] = f.finite();
      break;
    case 1:
      c.type = isur::MessageType::CartesianCommand;
      c.tool_count = static_cast<std::uint16_t>(1 + f.byte() % isur::kMaxTools);
      c.tool_mask = static_cast<std::uint16_t>(1 + f.byte() % ((1U << c.tool_count) - 1));
      for (std::size_t t = 0; t < c.tool_count; ++t) c.poses[t] = f.pose();
      break;
    default:
      c.type = isur::MessageType::ToolActuation;
      c.actuation.tool = static_cast<std::uint16_t>(f.byte() % isur::kMaxTools);
      c.actuation.request = f.u32() | 1U;
      break;
  }
  n = isur::encode(c, {f.u32(), 0}, out);
  isur::Command dc;
  if (n == 0 || isur::decode(std::span<const std::uint8_t>(out, n), dc, h) != wire::DecodeStatus::Ok) std::abort();
  if (dc.type != c.type) std::abort();
  if (c.type == isur::MessageType::JointCommand && (dc.joint_count != c.joint_count || dc.joints != c.joints))
    std::abort();
  if (c.type == isur::MessageType::CartesianCommand) {
    if (dc.tool_count != c.tool_count || dc.tool_mask != c.tool_mask) std::abort();
    for (std::size_t t = 0; t < c.tool_count; ++t)
      if (!samePose(dc.poses[t], c.poses[t])) std::abort();
  }
  if (c.type == isur::MessageType::ToolActuation &&
      (dc.actuation.tool != c.actuation.tool || dc.actuation.request != c.actuation.request))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  decodeBoth(std::span<const std::uint8_t>(data, size));
  roundTrip(data, size);
  // The same bytes with a correct CRC trailer: random mutations almost never match the CRC-32, so
  // without this the fuzzer would not get past the frame check to the payload decoders.
  if (size < wire::kHeaderSize + wire::kTrailerSize || size > isur::kMaxFrameSize) return 0;
  std::uint8_t framed[isur::kMaxFrameSize];
  std::memcpy(framed, data, size);
  const std::uint32_t crc = wire::crc32(std::span<const std::uint8_t>(framed, size - wire::kTrailerSize));
  for (std::size_t i = 0; i < 4; ++i) framed[size - 4 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
  decodeBoth(std::span<const std::uint8_t>(framed, size));
  return 0;
}
