#include "cobra/bridges/wire.hpp"

#include <bit>
#include <cmath>

namespace cobra::bridges::wire {

namespace {

constexpr std::array<std::string_view, kDecodeStatusCount> kNames = {
    "ok",        "truncated", "bad_magic", "bad_version", "bad_type", "bad_length",
    "bad_crc",   "non_finite", "bad_value", "late",       "delayed",  "wrong_joint_count", "wrong_tool_count"};

constexpr std::array<std::uint32_t, 256> makeCrcTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}
constexpr std::array<std::uint32_t, 256> kCrcTable = makeCrcTable();

}  // namespace

std::string_view toString(DecodeStatus status) noexcept {
  const auto i = static_cast<std::size_t>(status);
  return i < kNames.size() ? kNames[i] : std::string_view("unknown");
}

bool parseDecodeStatus(std::string_view name, DecodeStatus& out) noexcept {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) {
      out = static_cast<DecodeStatus>(i);
      return true;
    }
  }
  return false;
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept {
  std::uint32_t c = 0xFFFFFFFFU;
  for (const std::uint8_t b : bytes) c = kCrcTable[(c ^ b) & 0xFFU] ^ (c >> 8);
  return c ^ 0xFFFFFFFFU;
}

void Writer::bytes(std::uint64_t v, std::size_t n) noexcept {
  if (!ok_ || out_.size() - pos_ < n) {
    ok_ = false;
    return;
  }
  for (std::size_t i = 0; i < n; ++i) out_[pos_ + i] = static_cast<std::uint8_t>(v >> (8 * i));
  pos_ += n;
}

void Writer::f64(double v) noexcept { u64(std::bit_cast<std::uint64_t>(v)); }

void Writer::patchU32(std::size_t offset, std::uint32_t v) noexcept {
  if (!ok_ || offset + 4 > pos_) {
    ok_ = false;
    return;
  }
  for (std::size_t i = 0; i < 4; ++i) out_[offset + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint64_t Reader::bytes(std::size_t n) noexcept {
  if (!ok_ || in_.size() - pos_ < n) {
    ok_ = false;
    return 0;
  }
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(in_[pos_ + i]) << (8 * i);
  pos_ += n;
  return v;
}

double Reader::f64() noexcept { return std::bit_cast<double>(u64()); }

DecodeStatus peekHeader(std::span<const std::uint8_t> bytes, std::uint32_t magic, std::uint16_t version,
                        std::size_t max_payload, FrameHeader& header, std::size_t& frame_size) noexcept {
  if (bytes.size() < 4) return DecodeStatus::Truncated;
  Reader r(bytes);
  FrameHeader h;
  h.magic = r.u32();
  if (h.magic != magic) return DecodeStatus::BadMagic;
  if (bytes.size() < kHeaderSize) return DecodeStatus::Truncated;
  h.version = r.u16();
  h.type = r.u16();
  h.sequence = r.u32();
  h.timestamp_ns = r.u64();
  h.payload_length = r.u32();
  if (h.version != version) return DecodeStatus::BadVersion;
  if (h.payload_length > max_payload) return DecodeStatus::BadLength;
  header = h;
  frame_size = kHeaderSize + h.payload_length + kTrailerSize;
  return DecodeStatus::Ok;
}

DecodeStatus checkFrame(std::span<const std::uint8_t> bytes, std::uint32_t magic, std::uint16_t version,
                        std::size_t max_payload, FrameHeader& header, std::span<const std::uint8_t>& payload) noexcept {
  FrameHeader h;
  std::size_t frame_size = 0;
  if (const DecodeStatus s = peekHeader(bytes, magic, version, max_payload, h, frame_size); s != DecodeStatus::Ok)
    return s;
  if (bytes.size() < frame_size) return DecodeStatus::Truncated;
  if (bytes.size() > frame_size) return DecodeStatus::BadLength;
  Reader trailer(bytes.subspan(frame_size - kTrailerSize));
  if (trailer.u32() != crc32(bytes.first(frame_size - kTrailerSize))) return DecodeStatus::BadCrc;
  header = h;
  payload = bytes.subspan(kHeaderSize, h.payload_length);
  return DecodeStatus::Ok;
}

DecodeStatus LatenessFilter::accept(std::uint32_t sequence, std::uint64_t sender_ns, std::int64_t arrival_ns) noexcept {
  // Offsets in modular arithmetic: the two clocks need not share an origin.
  const auto offset = static_cast<std::int64_t>(static_cast<std::uint64_t>(arrival_ns) - sender_ns);
  if (has_last_) {
    const std::uint32_t ahead = sequence - last_sequence_;
    if (ahead == 0 || ahead >= 0x80000000U) return DecodeStatus::Late;
    if (max_delay_ns_ > 0 && offset - min_offset_ns_ > max_delay_ns_) return DecodeStatus::Delayed;
    if (offset < min_offset_ns_) min_offset_ns_ = offset;
  } else {
    min_offset_ns_ = offset;
    has_last_ = true;
  }
  last_sequence_ = sequence;
  return DecodeStatus::Ok;
}

bool allFinite(std::span<const double> values) noexcept {
  for (const double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace cobra::bridges::wire
