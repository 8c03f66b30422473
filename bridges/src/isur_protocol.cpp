#include "cobra/bridges/isur_protocol.hpp"

#include <cmath>

namespace cobra::bridges::isur {

namespace {

using wire::DecodeStatus;

void writePose(wire::Writer& w, const Pose& pose) noexcept {
  for (const double v : pose.position) w.f64(v);
  for (const double v : pose.quaternion) w.f64(v);
}

DecodeStatus readPose(wire::Reader& r, Pose& pose) noexcept {
  for (double& v : pose.position) v = r.f64();
  for (double& v : pose.quaternion) v = r.f64();
  if (!wire::allFinite(pose.position) || !wire::allFinite(pose.quaternion)) return DecodeStatus::NonFinite;
  const auto& q = pose.quaternion;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(std::abs(norm - 1.0) <= kQuatTolerance)) return DecodeStatus::BadValue;
  for (double& v : pose.quaternion) v /= norm;
  return DecodeStatus::Ok;
}

wire::FrameHeader header(MessageType type, const Stamp& stamp) noexcept {
  return {kMagic, kVersion, static_cast<std::uint16_t>(type), stamp.sequence, stamp.timestamp_ns, 0};
}

// Reads the u16 n | u16 flags | u32 reserved prefix shared by JointCommand and State.
DecodeStatus readJointPrefix(wire::Reader& r, std::size_t payload_length, std::size_t fixed, std::uint16_t& n,
                             std::uint16_t& flags) noexcept {
  if (payload_length < 8) return DecodeStatus::BadLength;
  n = r.u16();
  flags = r.u16();
  const std::uint32_t reserved = r.u32();
  if (n < 1 || n > kMaxJoints) return DecodeStatus::BadLength;
  if (payload_length != 8 + fixed + 8 * std::size_t{n}) return DecodeStatus::BadLength;
  if (reserved != 0) return DecodeStatus::BadValue;
  return DecodeStatus::Ok;
}

}  // namespace

std::size_t encode(const Command& command, const Stamp& stamp, std::span<std::uint8_t> out) noexcept {
  if (command.type == MessageType::JointCommand) {
    if (command.joint_count < 1 || command.joint_count > kMaxJoints) return 0;
    return wire::writeFrame(out, header(command.type, stamp), [&](wire::Writer& w) {
      w.u16(command.joint_count);
      w.u16(0);
      w.u32(0);
      for (std::size_t i = 0; i < command.joint_count; ++i) w.f64(command.joints[i]);
    });
  }
  if (command.type == MessageType::CartesianCommand)
    return wire::writeFrame(out, header(command.type, stamp), [&](wire::Writer& w) { writePose(w, command.pose); });
  return 0;
}

std::size_t encode(const State& state, const Stamp& stamp, std::span<std::uint8_t> out) noexcept {
  if (state.joint_count < 1 || state.joint_count > kMaxJoints) return 0;
  return wire::writeFrame(out, header(MessageType::State, stamp), [&](wire::Writer& w) {
    w.u16(state.joint_count);
    w.u16(state.flags);
    w.u32(0);
    for (std::size_t i = 0; i < state.joint_count; ++i) w.f64(state.joints[i]);
    writePose(w, state.pose);
    for (const double v : state.wrench) w.f64(v);
  });
}

DecodeStatus decode(std::span<const std::uint8_t> datagram, Command& out, wire::FrameHeader& header) noexcept {
  wire::FrameHeader h;
  std::span<const std::uint8_t> payload;
  const DecodeStatus framed = wire::checkFrame(datagram, kMagic, kVersion, kMaxPayload, h, payload);
  if (framed != DecodeStatus::Ok) return framed;
  wire::Reader r(payload);
  Command c;
  if (h.type == static_cast<std::uint16_t>(MessageType::JointCommand)) {
    c.type = MessageType::JointCommand;
    std::uint16_t flags = 0;
    if (const DecodeStatus s = readJointPrefix(r, payload.size(), 0, c.joint_count, flags); s != DecodeStatus::Ok)
      return s;
    if (flags != 0) return DecodeStatus::BadValue;
    for (std::size_t i = 0; i < c.joint_count; ++i) c.joints[i] = r.f64();
    if (!wire::allFinite(std::span<const double>(c.joints.data(), c.joint_count))) return DecodeStatus::NonFinite;
  } else if (h.type == static_cast<std::uint16_t>(MessageType::CartesianCommand)) {
    c.type = MessageType::CartesianCommand;
    if (payload.size() != 56) return DecodeStatus::BadLength;
    if (const DecodeStatus s = readPose(r, c.pose); s != DecodeStatus::Ok) return s;
  } else {
    return DecodeStatus::BadType;
  }
  out = c;
  header = h;
  return DecodeStatus::Ok;
}

DecodeStatus decode(std::span<const std::uint8_t> datagram, State& out, wire::FrameHeader& header) noexcept {
  wire::FrameHeader h;
  std::span<const std::uint8_t> payload;
  const DecodeStatus framed = wire::checkFrame(datagram, kMagic, kVersion, kMaxPayload, h, payload);
  if (framed != DecodeStatus::Ok) return framed;
  if (h.type != static_cast<std::uint16_t>(MessageType::State)) return DecodeStatus::BadType;
  wire::Reader r(payload);
  State st;
  if (const DecodeStatus s = readJointPrefix(r, payload.size(), 104, st.joint_count, st.flags); s != DecodeStatus::Ok)
    return s;
  if ((st.flags & ~kKnownStateFlags) != 0) return DecodeStatus::BadValue;
  for (std::size_t i = 0; i < st.joint_count; ++i) st.joints[i] = r.f64();
  if (!wire::allFinite(std::span<const double>(st.joints.data(), st.joint_count))) return DecodeStatus::NonFinite;
  if (const DecodeStatus s = readPose(r, st.pose); s != DecodeStatus::Ok) return s;
  for (double& v : st.wrench) v = r.f64();
  if (!wire::allFinite(st.wrench)) return DecodeStatus::NonFinite;
  out = st;
  header = h;
  return DecodeStatus::Ok;
}

}  // namespace cobra::bridges::isur
