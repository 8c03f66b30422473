#include "cobra/bridges/igtl_codec.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace cobra::bridges::igtl {

namespace {

constexpr std::uint64_t kPolynomial = 0x42F0E1EBA9EA3693ULL;
constexpr std::size_t kStringHeaderSize = 4;   // u16 encoding, u16 length
constexpr std::size_t kStatusHeaderSize = 30;  // u16 code, u64 subcode, char error_name[20]
constexpr std::uint16_t kAsciiMibEnum = 3;     // IANA MIBenum of US-ASCII

constexpr std::array<std::uint64_t, 256> makeTable() {
  std::array<std::uint64_t, 256> table{};
  for (std::uint64_t i = 0; i < 256; ++i) {
    std::uint64_t crc = i << 56;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & (1ULL << 63)) != 0 ? (crc << 1) ^ kPolynomial : crc << 1;
    table[i] = crc;
  }
  return table;
}
constexpr std::array<std::uint64_t, 256> kTable = makeTable();

// Big-endian readers over a span whose size the caller checked.
std::uint64_t readBig(const std::uint8_t* p, std::size_t bytes) noexcept {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}
float readFloat(const std::uint8_t* p) noexcept { return std::bit_cast<float>(static_cast<std::uint32_t>(readBig(p, 4))); }

void writeBig(std::uint8_t* p, std::uint64_t v, std::size_t bytes) noexcept {
  for (std::size_t i = 0; i < bytes; ++i) p[bytes - 1 - i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void writeFloat(std::uint8_t* p, double v) noexcept {
  writeBig(p, std::bit_cast<std::uint32_t>(static_cast<float>(v)), 4);
}

// A NUL-padded name field: printable ASCII, then only NULs. Empty names are allowed.
bool readName(const std::uint8_t* p, std::size_t field, std::string_view& out) noexcept {
  std::size_t n = 0;
  while (n < field && p[n] != 0) {
    if (p[n] < 0x20 || p[n] > 0x7E) return false;
    ++n;
  }
  for (std::size_t i = n; i < field; ++i)
    if (p[i] != 0) return false;
  out = std::string_view(reinterpret_cast<const char*>(p), n);
  return true;
}

// A text field of `field` bytes read up to its first NUL (any bytes; no check).
std::string_view cString(const std::uint8_t* p, std::size_t field) noexcept {
  std::size_t n = 0;
  while (n < field && p[n] != 0) ++n;
  return {reinterpret_cast<const char*>(p), n};
}

void writeName(std::uint8_t* p, std::size_t field, std::string_view name) noexcept {
  std::memset(p, 0, field);
  std::memcpy(p, name.data(), std::min(name.size(), field));
}

// Writes the header of a message of `type` whose body is out[kHeaderSize, kHeaderSize + body).
void finish(std::string_view type, std::string_view device, std::uint64_t timestamp, std::size_t body,
            std::span<std::uint8_t> out) noexcept {
  std::uint8_t* p = out.data();
  writeBig(p, kHeaderVersion, 2);
  writeName(p + 2, kTypeSize, type);
  writeName(p + 14, kDeviceSize, device);
  writeBig(p + 34, timestamp, 8);
  writeBig(p + 42, body, 8);
  writeBig(p + 50, crc64(std::span<const std::uint8_t>(p + kHeaderSize, body)), 8);
}

bool finiteAll(const double* v, std::size_t n) noexcept {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

IgtlError decodeTransform(std::span<const std::uint8_t> body, Transform& out) noexcept {
  if (body.size() != 48) return IgtlError::BadBody;
  // The wire holds the upper 3x4 matrix column by column: R(:,0), R(:,1), R(:,2), p (mm).
  double m[12];
  for (std::size_t i = 0; i < 12; ++i) m[i] = readFloat(body.data() + 4 * i);
  if (!finiteAll(m, 12)) return IgtlError::BadBody;
  for (std::size_t c = 0; c < 4; ++c)
    for (std::size_t r = 0; r < 3; ++r) out.matrix[r][c] = c < 3 ? m[3 * c + r] : m[9 + r] * 1e-3;
  // A rotation (float precision on the wire): orthonormal columns within 1e-3, determinant +1.
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b) {
      double dot = 0.0;
      for (std::size_t r = 0; r < 3; ++r) dot += out.matrix[r][a] * out.matrix[r][b];
      if (std::abs(dot - (a == b ? 1.0 : 0.0)) > 1e-3) return IgtlError::BadBody;
    }
  const auto& R = out.matrix;
  const double det = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) - R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
                     R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
  return det > 0.0 ? IgtlError::Ok : IgtlError::BadBody;
}

IgtlError decodePoints(std::span<const std::uint8_t> body, Points& out) noexcept {
  if (body.size() % kPointElementSize != 0) return IgtlError::BadBody;
  out.total = body.size() / kPointElementSize;
  out.count = std::min(out.total, kMaxPoints);
  for (std::size_t k = 0; k < out.count; ++k) {
    // char name[64], char group[32], u8 rgba[4], f32 position[3] (mm), f32 radius, char owner[20]
    const std::uint8_t* e = body.data() + k * kPointElementSize;
    Point& p = out.points[k];
    p.name.assign(cString(e, 64));
    p.group.assign(cString(e + 64, 32));
    for (std::size_t i = 0; i < 3; ++i) p.position[i] = readFloat(e + 100 + 4 * i) * 1e-3;
    if (!finiteAll(p.position, 3)) return IgtlError::BadBody;
  }
  return IgtlError::Ok;
}

IgtlError decodeString(std::span<const std::uint8_t> body, Chars<kMaxText>& out) noexcept {
  if (body.size() < kStringHeaderSize) return IgtlError::BadBody;
  const std::size_t length = readBig(body.data() + 2, 2);
  if (body.size() != kStringHeaderSize + length) return IgtlError::BadBody;
  out.assign(std::string_view(reinterpret_cast<const char*>(body.data() + kStringHeaderSize), length));
  return IgtlError::Ok;
}

IgtlError decodeStatus(std::span<const std::uint8_t> body, Status& out) noexcept {
  if (body.size() < kStatusHeaderSize) return IgtlError::BadBody;
  out.code = static_cast<std::uint16_t>(readBig(body.data(), 2));
  out.subcode = static_cast<std::int64_t>(readBig(body.data() + 2, 8));
  out.error_name.assign(cString(body.data() + 10, 20));
  out.text.assign(cString(body.data() + kStatusHeaderSize, body.size() - kStatusHeaderSize));
  return IgtlError::Ok;
}

}  // namespace


std::string_view reasonName(IgtlError error) noexcept {
  switch (error) {
    case IgtlError::Ok: return "ok";
    case IgtlError::Truncated: return "truncated";
    case IgtlError::BadHeader: return "bad_header";
    case IgtlError::Oversized: return "oversized";
    case IgtlError::BadCrc: return "bad_crc";
    case IgtlError::UnknownType: return "unknown_type";
    case IgtlError::BadBody: return "bad_body";
  }
  return "unknown";
}

std::uint64_t crc64(std::span<const std::uint8_t> bytes, std::uint64_t crc) noexcept {
  for (const std::uint8_t b : bytes) crc = kTable[((crc >> 56) ^ b) & 0xFF] ^ (crc << 8);
  return crc;
}

std::uint64_t wireTimestamp(std::uint64_t ns) noexcept {
  const std::uint64_t seconds = ns / 1000000000ULL;
  const std::uint64_t rest = ns % 1000000000ULL;
  return (seconds << 32) | ((rest << 32) / 1000000000ULL);
}

IgtlError decodeHeader(std::span<const std::uint8_t> bytes, Header& out) noexcept {
  if (bytes.size() < kHeaderSize) return IgtlError::Truncated;
  const std::uint8_t* p = bytes.data();
  out.version = static_cast<std::uint16_t>(readBig(p, 2));
  std::string_view type, device;
  if ((out.version != kHeaderVersion && out.version != kHeaderVersion2) || !readName(p + 2, kTypeSize, type) || type.empty() ||
      !readName(p + 14, kDeviceSize, device))
    return IgtlError::BadHeader;
  out.type.assign(type);
  out.device.assign(device);
  out.timestamp = readBig(p + 34, 8);
  out.body_size = readBig(p + 42, 8);
  out.crc = readBig(p + 50, 8);
  return IgtlError::Ok;
}

IgtlError decodeBody(const Header& header, std::span<const std::uint8_t> body, Message& out) noexcept {
  if (body.size() != header.body_size) return IgtlError::Truncated;
  if (crc64(body) != header.crc) return IgtlError::BadCrc;
  if (header.version == kHeaderVersion2) {
    // Extended header: u16 its size (>= 12), u16 metadata header size, u32 metadata size, u32
    // message id; then the content; then the metadata header and the metadata, skipped.
    if (body.size() < kExtendedHeaderSize) return IgtlError::BadBody;
    const std::uint64_t extended = readBig(body.data(), 2);
    const std::uint64_t metadata = readBig(body.data() + 2, 2) + readBig(body.data() + 4, 4);
    if (extended < kExtendedHeaderSize || extended + metadata > body.size()) return IgtlError::BadBody;
    body = body.subspan(static_cast<std::size_t>(extended), static_cast<std::size_t>(body.size() - extended - metadata));
  }
  out.device = header.device;
  out.timestamp = header.timestamp;
  const std::string_view type = header.type.view();
  if (type == "TRANSFORM") {
    out.type = MessageType::Transform;
    return decodeTransform(body, out.transform);
  }
  if (type == "POINT") {
    out.type = MessageType::Point;
    return decodePoints(body, out.points);
  }
  if (type == "STRING") {
    out.type = MessageType::String;
    return decodeString(body, out.text);
  }
  if (type == "STATUS") {
    out.type = MessageType::Status;
    return decodeStatus(body, out.status);
  }
  return IgtlError::UnknownType;
}

IgtlError decode(std::span<const std::uint8_t> bytes, std::size_t max_body, Message& out) noexcept {
  Header header;
  if (const IgtlError e = decodeHeader(bytes, header); e != IgtlError::Ok) return e;
  if (header.body_size > max_body) return IgtlError::Oversized;
  if (bytes.size() - kHeaderSize < header.body_size) return IgtlError::Truncated;
  return decodeBody(header, bytes.subspan(kHeaderSize, static_cast<std::size_t>(header.body_size)), out);
}

std::size_t encodeTransform(std::string_view device, const Transform& transform, std::uint64_t timestamp,
                            std::span<std::uint8_t> out) noexcept {
  if (out.size() < kTransformMessageSize) return 0;
  if (!finiteAll(&transform.matrix[0][0], 12)) return 0;
  std::uint8_t* body = out.data() + kHeaderSize;
  for (std::size_t c = 0; c < 4; ++c)
    for (std::size_t r = 0; r < 3; ++r)
      writeFloat(body + 4 * (3 * c + r), c < 3 ? transform.matrix[r][c] : transform.matrix[r][3] * 1e3);
  finish("TRANSFORM", device, timestamp, 48, out);
  return kTransformMessageSize;
}

std::size_t encodeStatus(std::string_view device, std::uint16_t code, std::int64_t subcode, std::string_view error_name,
                         std::string_view text, std::uint64_t timestamp, std::span<std::uint8_t> out) noexcept {
  text = text.substr(0, std::min(text.size(), kMaxText));
  const std::size_t body = kStatusHeaderSize + text.size() + 1;  // the status string ends with a NUL
  if (out.size() < kHeaderSize + body) return 0;
  std::uint8_t* p = out.data() + kHeaderSize;
  writeBig(p, code, 2);
  writeBig(p + 2, static_cast<std::uint64_t>(subcode), 8);
  writeName(p + 10, 20, error_name.substr(0, std::min<std::size_t>(error_name.size(), 19)));
  std::memcpy(p + kStatusHeaderSize, text.data(), text.size());
  p[kStatusHeaderSize + text.size()] = 0;
  finish("STATUS", device, timestamp, body, out);
  return kHeaderSize + body;
}

std::size_t encodeString(std::string_view device, std::string_view text, std::uint64_t timestamp,
                         std::span<std::uint8_t> out) noexcept {
  text = text.substr(0, std::min(text.size(), kMaxText));
  const std::size_t body = kStringHeaderSize + text.size();
  if (out.size() < kHeaderSize + body) return 0;
  std::uint8_t* p = out.data() + kHeaderSize;
  writeBig(p, kAsciiMibEnum, 2);
  writeBig(p + 2, text.size(), 2);
  std::memcpy(p + kStringHeaderSize, text.data(), text.size());
  finish("STRING", device, timestamp, body, out);
  return kHeaderSize + body;
}

std::size_t encodeImage(std::string_view device, const ImageView& image, std::uint64_t timestamp,
                        std::span<std::uint8_t> out) noexcept {
  const std::size_t w = image.width, h = image.height;
  if (w == 0 || h == 0 || w > 0xFFFF || h > 0xFFFF || image.pixels == nullptr) return 0;
  if (!(image.spacing_x > 0.0 && image.spacing_y > 0.0 && std::isfinite(image.spacing_x) && std::isfinite(image.spacing_y)))
    return 0;
  if (!finiteAll(&image.corner.matrix[0][0], 12)) return 0;
  const std::size_t size = imageMessageSize(w, h);
  if (out.size() < size) return 0;
  std::uint8_t* p = out.data() + kHeaderSize;
  writeBig(p, 1, 2);   // image header version
  p[2] = 1;            // components per pixel
  p[3] = 3;            // scalar type uint8
  p[4] = 1;            // endian: big (irrelevant for 8-bit pixels)
  p[5] = 1;            // coordinate system RAS: cobra's world frame is sent as it is
  writeBig(p + 6, w, 2);
  writeBig(p + 8, h, 2);
  writeBig(p + 10, 1, 2);
  const auto& M = image.corner.matrix;
  const double scale[3] = {image.spacing_x * 1e3, image.spacing_y * 1e3, 1.0};  // mm per index along i, j, k
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t r = 0; r < 3; ++r) writeFloat(p + 12 + 4 * (3 * c + r), M[r][c] * scale[c]);
  const double half_x = 0.5 * static_cast<double>(w - 1) * image.spacing_x;
  const double half_y = 0.5 * static_cast<double>(h - 1) * image.spacing_y;
  for (std::size_t r = 0; r < 3; ++r)
    writeFloat(p + 48 + 4 * r, (M[r][3] + M[r][0] * half_x + M[r][1] * half_y) * 1e3);
  for (std::size_t i = 0; i < 3; ++i) writeBig(p + 60 + 2 * i, 0, 2);  // sub-volume offset
  writeBig(p + 66, w, 2);
  writeBig(p + 68, h, 2);
  writeBig(p + 70, 1, 2);
  std::memcpy(p + kImageHeaderSize, image.pixels, w * h);
  finish("IMAGE", device, timestamp, kImageHeaderSize + w * h, out);
  return size;
}

}  // namespace cobra::bridges::igtl
