// libFuzzer target: the OpenIGTLink decoder (bridges/include/cobra/bridges/igtl_codec.hpp) on
// arbitrary bytes, whole and as a header then a body. A decoded message stays within its fixed
// capacities, and what the codec also encodes (TRANSFORM, STRING, STATUS) decodes again to the
// same record.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "cobra/bridges/igtl_codec.hpp"

namespace {

using namespace cobra::bridges::igtl;

void check(bool ok) {
  if (!ok) std::abort();
}

// Re-encodes `m` (when the codec encodes its type) and decodes it again: the same record back.
void roundTrip(const Message& m) {
  static std::uint8_t out[kHeaderSize + 64 + kMaxText];
  Message again;
  std::size_t size = 0;
  switch (m.type) {
    case MessageType::Transform: size = encodeTransform(m.device.view(), m.transform, m.timestamp, out); break;
    case MessageType::String: size = encodeString(m.device.view(), m.text.view(), m.timestamp, out); break;
    case MessageType::Status:
      size = encodeStatus(m.device.view(), m.status.code, m.status.subcode, m.status.error_name.view(),
                          m.status.text.view(), m.timestamp, out);
      break;
    case MessageType::Point: return;  // decoded only
  }
  check(size > 0);
  check(decode(std::span<const std::uint8_t>(out, size), sizeof out, again) == IgtlError::Ok);
  check(again.type == m.type && again.device.view() == m.device.view() && again.timestamp == m.timestamp);
  if (m.type == MessageType::String) check(again.text.view().substr(0, again.text.size) == m.text.view().substr(0, again.text.size));
  if (m.type == MessageType::Transform)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) check(std::abs(again.transform.matrix[r][c] - m.transform.matrix[r][c]) <= 1e-3);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  static Message m;
  const IgtlError whole = decode(bytes, 1 << 16, m);
  if (whole == IgtlError::Ok) {
    check(m.points.count <= kMaxPoints && m.text.size <= kMaxText && m.status.text.size <= kMaxText);
    check(m.device.size <= kDeviceSize);
    roundTrip(m);
  }
  // The same bytes read as the bridge's link reads a stream: the header, then exactly its body
  // (a body over the limit the whole decode was given is refused as Oversized there, and never
  // reaches decodeBody on the link: compared only within it).
  Header header;
  if (decodeHeader(bytes, header) == IgtlError::Ok && header.body_size <= size - kHeaderSize &&
      header.body_size <= (1u << 16)) {
    static Message part;
    const auto body = bytes.subspan(kHeaderSize, static_cast<std::size_t>(header.body_size));
    check(decodeBody(header, body, part) == whole);
  }
  return 0;
}
