// libFuzzer target: the I-SUR UDP decoders (commands and states) on arbitrary datagrams. A decoded
// message must re-encode to the same bytes, except for the quaternion, which the decoder normalises.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "cobra/bridges/isur_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cobra::bridges;
  const std::span<const std::uint8_t> bytes(data, size);
  wire::FrameHeader header;
  isur::State state;
  if (isur::decode(bytes, state, header) == wire::DecodeStatus::Ok) {
    if (state.joint_count < 1 || state.joint_count > isur::kMaxJoints) std::abort();
    std::uint8_t out[isur::kMaxFrameSize];
    if (isur::encode(state, {header.sequence, header.timestamp_ns}, out) != size) std::abort();
  }
  isur::Command command;
  if (isur::decode(bytes, command, header) == wire::DecodeStatus::Ok) {
    std::uint8_t out[isur::kMaxFrameSize];
    if (isur::encode(command, {header.sequence, header.timestamp_ns}, out) != size) std::abort();
  }
  return 0;
}
