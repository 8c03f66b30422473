#include "cobra/bridges/omni_protocol.hpp"

#include <cmath>

namespace cobra::bridges::omni {

namespace {
using wire::DecodeStatus;
}  // namespace

std::size_t encode(const State& state, const Stamp& stamp, std::span<std::uint8_t> out) noexcept {
  const wire::FrameHeader h{kMagic, kVersion, static_cast<std::uint16_t>(MessageType::State), stamp.sequence,
                            stamp.timestamp_ns, 0};
  return wire::writeFrame(out, h, [&](wire::Writer& w) {
    for (const double v : state.position) w.f64(v);
    for (const double v : state.quaternion) w.f64(v);
    for (const double v : state.twist) w.f64(v);
    w.u32(state.buttons);
    w.u32(0);
  });
}

std::size_t encode(const WrenchCommand& command, const Stamp& stamp, std::span<std::uint8_t> out) noexcept {
  const wire::FrameHeader h{kMagic, kVersion, static_cast<std::uint16_t>(MessageType::WrenchCommand),
                            stamp.sequence, stamp.timestamp_ns, 0};
  return wire::writeFrame(out, h, [&](wire::Writer& w) {
    for (const double v : command.wrench) w.f64(v);
  });
}

DecodeStatus decode(std::span<const std::uint8_t> frame, State& out, wire::FrameHeader& header) noexcept {
  wire::FrameHeader h;
  std::span<const std::uint8_t> payload;
  if (const DecodeStatus s = wire::checkFrame(frame, kMagic, kVersion, kMaxPayload, h, payload); s != DecodeStatus::Ok)
    return s;
  if (h.type != static_cast<std::uint16_t>(MessageType::State)) return DecodeStatus::BadType;
  if (payload.size() != kStatePayload) return DecodeStatus::BadLength;
  wire::Reader r(payload);
  State st;
  for (double& v : st.position) v = r.f64();
  for (double& v : st.quaternion) v = r.f64();
  for (double& v : st.twist) v = r.f64();
  st.buttons = r.u32();
  const std::uint32_t reserved = r.u32();
  if (!wire::allFinite(st.position) || !wire::allFinite(st.quaternion) || !wire::allFinite(st.twist))
    return DecodeStatus::NonFinite;
  const auto& q = st.quaternion;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(std::abs(norm - 1.0) <= kQuatTolerance)) return DecodeStatus::BadValue;
  if ((st.buttons & ~kKnownButtons) != 0 || reserved != 0) return DecodeStatus::BadValue;
  for (double& v : st.quaternion) v /= norm;
  out = st;
  header = h;
  return DecodeStatus::Ok;
}

DecodeStatus decode(std::span<const std::uint8_t> frame, WrenchCommand& out, wire::FrameHeader& header) noexcept {
  wire::FrameHeader h;
  std::span<const std::uint8_t> payload;
  if (const DecodeStatus s = wire::checkFrame(frame, kMagic, kVersion, kMaxPayload, h, payload); s != DecodeStatus::Ok)
    return s;
  if (h.type != static_cast<std::uint16_t>(MessageType::WrenchCommand)) return DecodeStatus::BadType;
  if (payload.size() != kWrenchPayload) return DecodeStatus::BadLength;
  wire::Reader r(payload);
  WrenchCommand c;
  for (double& v : c.wrench) v = r.f64();
  if (!wire::allFinite(c.wrench)) return DecodeStatus::NonFinite;
  out = c;
  header = h;
  return DecodeStatus::Ok;
}

}  // namespace cobra::bridges::omni
