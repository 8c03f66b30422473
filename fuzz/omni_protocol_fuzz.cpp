// libFuzzer target: the Omni TCP decoders and the stream framer on arbitrary byte streams.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "cobra/bridges/omni_protocol.hpp"
#include "cobra/bridges/stream_framer.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cobra::bridges;
  const std::span<const std::uint8_t> bytes(data, size);
  wire::FrameHeader header;
  omni::State state;
  if (omni::decode(bytes, state, header) == wire::DecodeStatus::Ok) {
    if ((state.buttons & ~omni::kKnownButtons) != 0) std::abort();
    std::uint8_t out[omni::kMaxFrameSize];
    if (omni::encode(state, {header.sequence, header.timestamp_ns}, out) != size) std::abort();
  }
  omni::WrenchCommand command;
  (void)omni::decode(bytes, command, header);
  // The same bytes as a stream arriving in chunks of 7: the framer must never overrun.
  StreamFramer framer(omni::kMagic, omni::kVersion, omni::kMaxPayload);
  std::size_t offset = 0;
  while (offset < size) {
    auto space = framer.space();
    std::size_t n = size - offset < 7 ? size - offset : 7;
    if (n > space.size()) std::abort();
    for (std::size_t i = 0; i < n; ++i) space[i] = data[offset + i];
    framer.commit(n);
    offset += n;
    std::span<const std::uint8_t> frame;
    wire::DecodeStatus why;
    StreamFramer::Next next;
    while ((next = framer.next(frame, why)) == StreamFramer::Next::Frame) (void)omni::decode(frame, state, header);
    if (next == StreamFramer::Next::Broken) break;
  }
  return 0;
}
