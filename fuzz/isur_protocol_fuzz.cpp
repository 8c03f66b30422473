// libFuzzer target: the I-SUR UDP decoders (commands: joints, Cartesian poses for 1..kMaxTools
// tools, tool actuations; states with 1..kMaxTools tools) on arbitrary datagrams, as they come and
// with their CRC trailer made correct. A decoded message
// must satisfy the documented ranges and re-encode to the same bytes, except for the quaternions,
// which the decoder normalises (the same length, and a decode of the re-encoding gives the same
// message).
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  decodeBoth(std::span<const std::uint8_t>(data, size));
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
