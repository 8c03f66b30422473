#pragma once
/// @file
/// OpenIGTLink as fixed-size records (header version 1, as libOpenIGTLink 1.x sends and every
/// receiver reads; version 2, of protocol 3, is read too: its extended header and metadata are
/// skipped): decode TRANSFORM, POINT, STRING and STATUS messages; encode TRANSFORM,
/// STATUS, STRING and IMAGE. No cobra::core, no I/O, no heap, no exception: the decoder takes any
/// bytes (it is fuzzed, fuzz/igtl_message_fuzz.cpp) and says what is wrong by an `IgtlError`.
///
/// Wire (big-endian): a 58-byte header `u16 version (1)`, `char type[12]`, `char device[20]`
/// (NUL-padded ASCII), `u64 timestamp` (seconds << 32 | fraction of 2^-32 s), `u64 body_size`,
/// `u64 crc` (CRC-64 ECMA-182 of the body), then the body. Lengths on the wire are mm; every
/// record here is in m.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

namespace cobra::bridges::igtl {

inline constexpr std::size_t kHeaderSize = 58;       ///< bytes of a message header
inline constexpr std::size_t kTypeSize = 12;         ///< bytes of the type name field
inline constexpr std::size_t kDeviceSize = 20;       ///< bytes of the device name field
inline constexpr std::uint16_t kHeaderVersion = 1;   ///< the header version sent
inline constexpr std::uint16_t kHeaderVersion2 = 2;  ///< read too: the body starts with an extended header
inline constexpr std::size_t kExtendedHeaderSize = 12;  ///< bytes of a version 2 extended header, at least
inline constexpr std::size_t kMaxPoints = 32;        ///< POINT elements kept (types::PointList's capacity)
inline constexpr std::size_t kMaxText = 255;         ///< characters of a STRING / STATUS text kept
inline constexpr std::size_t kPointElementSize = 136;  ///< bytes of one POINT element
inline constexpr std::size_t kImageHeaderSize = 72;    ///< bytes of the IMAGE body's own header

/// Why a message was not decoded. Names (reasonName) are at most 15 characters.
enum class IgtlError : std::uint8_t {
  Ok,
  Truncated,    ///< fewer bytes than the header or its body_size says
  BadHeader,    ///< version not 1 or 2, or a type / device name that is not NUL-padded printable ASCII
  Oversized,    ///< body_size above the receiver's limit
  BadCrc,       ///< the body's CRC-64 differs from the header's
  UnknownType,  ///< a type this codec does not decode (IMAGE, POSITION, ...)
  BadBody,      ///< a body whose size or contents do not fit its type (a NaN, a partial element), or
                ///< a version 2 extended header whose sizes do not fit the body
};
std::string_view reasonName(IgtlError error) noexcept;

enum class MessageType : std::uint8_t { Transform, Point, String, Status };

/// A fixed-capacity NUL-terminated name or text.
template <std::size_t N>
struct Chars {
  std::array<char, N + 1> chars{};
  std::size_t size = 0;
  std::string_view view() const noexcept { return {chars.data(), size}; }
  /// Copies `text`, cut to N characters.
  void assign(std::string_view text) noexcept {
    size = text.size() < N ? text.size() : N;
    std::memcpy(chars.data(), text.data(), size);
    chars[size] = '\0';
  }
};

/// The header of a message, decoded.
struct Header {
  std::uint16_t version = 0;
  Chars<kTypeSize> type;
  Chars<kDeviceSize> device;
  std::uint64_t timestamp = 0;  ///< the wire's fixed point: seconds << 32 | fraction
  std::uint64_t body_size = 0;  ///< bytes
  std::uint64_t crc = 0;
};

/// A rigid transform: rotation rows R[r][0..2] and translation (m) in column 3.
struct Transform {
  double matrix[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
};

struct Point {
  Chars<31> name;      ///< the element's name (cut to 31 characters)
  Chars<31> group;     ///< its group name
  double position[3];  ///< m
};

struct Points {
  std::size_t count = 0;  ///< elements kept (the first kMaxPoints)
  std::size_t total = 0;  ///< elements in the message
  Point points[kMaxPoints];
};

struct Status {
  std::uint16_t code = 1;  ///< 1 OK, 2 unknown, ... (OpenIGTLink's STATUS codes)
  std::int64_t subcode = 0;
  Chars<20> error_name;
  Chars<kMaxText> text;
};

/// One decoded message. Trivially copyable: it crosses the bridge's SPSC ring.
struct Message {
  MessageType type = MessageType::String;
  Chars<kDeviceSize> device;
  std::uint64_t timestamp = 0;
  Transform transform;  ///< TRANSFORM
  Points points;        ///< POINT
  Chars<kMaxText> text; ///< STRING (cut to kMaxText characters)
  Status status;        ///< STATUS
};

/// Reads a header from its first kHeaderSize bytes: Truncated, BadHeader or Ok.
IgtlError decodeHeader(std::span<const std::uint8_t> bytes, Header& out) noexcept;

/// Decodes the body of a message whose header is `header` (body.size() must be header.body_size,
/// else Truncated): CRC, then the type's contents.
IgtlError decodeBody(const Header& header, std::span<const std::uint8_t> body, Message& out) noexcept;

/// Decodes one whole message (header and body); bodies above `max_body` bytes are Oversized.
IgtlError decode(std::span<const std::uint8_t> bytes, std::size_t max_body, Message& out) noexcept;

/// CRC-64 ECMA-182 (polynomial 0x42F0E1EBA9EA3693, initial 0, not reflected), as OpenIGTLink.
std::uint64_t crc64(std::span<const std::uint8_t> bytes, std::uint64_t crc = 0) noexcept;

/// The wire timestamp of `ns` nanoseconds.
std::uint64_t wireTimestamp(std::uint64_t ns) noexcept;

// ---- encoders: each writes one whole message into `out` and returns its size, 0 when `out` is too
// small or an argument is out of range. Device names are cut to 20 characters.

inline constexpr std::size_t kTransformMessageSize = kHeaderSize + 48;

/// TRANSFORM of `transform` (translation m -> mm on the wire).
std::size_t encodeTransform(std::string_view device, const Transform& transform, std::uint64_t timestamp,
                            std::span<std::uint8_t> out) noexcept;
/// STATUS: code, subcode, error name (cut to 19), status text (cut to kMaxText).
std::size_t encodeStatus(std::string_view device, std::uint16_t code, std::int64_t subcode, std::string_view error_name,
                         std::string_view text, std::uint64_t timestamp, std::span<std::uint8_t> out) noexcept;
/// STRING in US-ASCII (MIBenum 3), text cut to kMaxText.
std::size_t encodeString(std::string_view device, std::string_view text, std::uint64_t timestamp,
                         std::span<std::uint8_t> out) noexcept;

/// An 8-bit grey image: width x height pixels (1..65535 each), spacing (m per pixel) along
/// columns and rows, `corner` the frame of pixel (0, 0) (m; x along columns, y along rows).
struct ImageView {
  std::size_t width = 0;
  std::size_t height = 0;
  double spacing_x = 0.0;
  double spacing_y = 0.0;
  Transform corner;
  const std::uint8_t* pixels = nullptr;  ///< width * height bytes, row-major
};
/// The size of the IMAGE message of a `width` x `height` image.
constexpr std::size_t imageMessageSize(std::size_t width, std::size_t height) {
  return kHeaderSize + kImageHeaderSize + width * height;
}
/// IMAGE (scalar uint8, one slice, RAS): its matrix columns are the column and row directions
/// times the spacing (mm) and the slice normal (1 mm); its origin is the image's centre, as
/// OpenIGTLink receivers (3D Slicer) read it: corner · [(w − 1)/2 · sx, (h − 1)/2 · sy, 0] (mm).
std::size_t encodeImage(std::string_view device, const ImageView& image, std::uint64_t timestamp,
                        std::span<std::uint8_t> out) noexcept;

}  // namespace cobra::bridges::igtl
