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

bool validJointCount(std::uint16_t n) noexcept { return n >= 1 && n <= kMaxJoints; }
bool validToolCount(std::uint16_t m) noexcept { return m >= 1 && m <= kMaxTools; }
/// At least one tool, none at or above m.
bool validMask(std::uint16_t mask, std::uint16_t m) noexcept { return mask != 0 && (mask >> m) == 0; }
/// Known flags, and no tool-1 flag on a one-tool robot.
bool validFlags(std::uint16_t flags, std::uint16_t m) noexcept {
  return (flags & ~kKnownStateFlags) == 0 && (m > 1 || (flags & kWrenchSaturatedTool1) == 0);
}

DecodeStatus decodeJointCommand(wire::Reader& r, std::size_t length, Command& c) noexcept {
  if (length < 8) return DecodeStatus::BadLength;
  c.joint_count = r.u16();
  const std::uint16_t reserved16 = r.u16();
  const std::uint32_t reserved32 = r.u32();
  if (!validJointCount(c.joint_count) || length != 8 + 8 * std::size_t{c.joint_count}) return DecodeStatus::BadLength;
  if (reserved16 != 0 || reserved32 != 0) return DecodeStatus::BadValue;
  for (std::size_t i = 0; i < c.joint_count; ++i) c.joints[i] = r.f64();
  if (!wire::allFinite(std::span<const double>(c.joints.data(), c.joint_count))) return DecodeStatus::NonFinite;
  return DecodeStatus::Ok;
}

DecodeStatus decodeCartesianCommand(wire::Reader& r, std::size_t length, Command& c) noexcept {
  if (length < 8) return DecodeStatus::BadLength;
  c.tool_count = r.u16();
  c.tool_mask = r.u16();
  const std::uint32_t reserved = r.u32();
  if (!validToolCount(c.tool_count)) return DecodeStatus::BadValue;
  if (length != 8 + 56 * std::size_t{c.tool_count}) return DecodeStatus::BadLength;
  if (reserved != 0 || !validMask(c.tool_mask, c.tool_count)) return DecodeStatus::BadValue;
  for (std::size_t t = 0; t < c.tool_count; ++t)
    if (const DecodeStatus s = readPose(r, c.poses[t]); s != DecodeStatus::Ok) return s;
  return DecodeStatus::Ok;
}

DecodeStatus decodeToolActuation(wire::Reader& r, std::size_t length, Command& c) noexcept {
  if (length != 8) return DecodeStatus::BadLength;
  c.actuation.tool = r.u16();
  const std::uint16_t reserved = r.u16();
  c.actuation.request = r.u32();
  if (c.actuation.tool >= kMaxTools || reserved != 0 || c.actuation.request == 0) return DecodeStatus::BadValue;
  return DecodeStatus::Ok;
}

}  // namespace

std::size_t encode(const Command& command, const Stamp& stamp, std::span<std::uint8_t> out) noexcept {
  switch (command.type) {
    case MessageType::JointCommand:
      if (!validJointCount(command.joint_count)) return 0;
      return wire::writeFrame(out, header(command.type, stamp), [&](wire::Writer& w) {
        w.u16(command.joint_count);
        w.u16(0);
        w.u32(0);
        for (std::size_t i = 0; i < command.joint_count; ++i) w.f64(command.joints[i]);
      });
    case MessageType::CartesianCommand:
      if (!validToolCount(command.tool_count) || !validMask(command.tool_mask, command.tool_count)) return 0;
      return wire::writeFrame(out, header(command.type, stamp), [&](wire::Writer& w) {
        w.u16(command.tool_count);
        w.u16(command.tool_mask);
        w.u32(0);
        for (std::size_t t = 0; t < command.tool_count; ++t) writePose(w, command.poses[t]);
      });
    case MessageType::ToolActuation:
      if (command.actuation.tool >= kMaxTools || command.actuation.request == 0) return 0;
      return wire::writeFrame(out, header(command.type, stamp), [&](wire::Writer& w) {
        w.u16(command.actuation.tool);
        w.u16(0);
        w.u32(command.actuation.request);
      });
    case MessageType::State: break;
  }
  return 0;
}

std::size_t encode(const State& state, const Stamp& stamp, std::span<std::uint8_t> out) noexcept {
  if (!validJointCount(state.joint_count) || !validToolCount(state.tool_count) ||
      !validFlags(state.flags, state.tool_count))
    return 0;
  return wire::writeFrame(out, header(MessageType::State, stamp), [&](wire::Writer& w) {
    w.u16(state.joint_count);
    w.u16(state.flags);
    w.u16(state.tool_count);
    w.u16(0);
    w.u32(state.actuations);
    w.u32(state.actuation_request);
    for (std::size_t i = 0; i < state.joint_count; ++i) w.f64(state.joints[i]);
    for (std::size_t t = 0; t < state.tool_count; ++t) {
      writePose(w, state.tools[t].pose);
      for (const double v : state.tools[t].wrench) w.f64(v);
    }
  });
}

DecodeStatus decode(std::span<const std::uint8_t> datagram, Command& out, wire::FrameHeader& header) noexcept {
  wire::FrameHeader h;
  std::span<const std::uint8_t> payload;
  const DecodeStatus framed = wire::checkFrame(datagram, kMagic, kVersion, kMaxPayload, h, payload);
  if (framed != DecodeStatus::Ok) return framed;
  wire::Reader r(payload);
  Command c;
  DecodeStatus status = DecodeStatus::BadType;
  switch (static_cast<MessageType>(h.type)) {
    case MessageType::JointCommand: status = decodeJointCommand(r, payload.size(), c); break;
    case MessageType::CartesianCommand: status = decodeCartesianCommand(r, payload.size(), c); break;
    case MessageType::ToolActuation: status = decodeToolActuation(r, payload.size(), c); break;
    case MessageType::State: break;
  }
  if (status != DecodeStatus::Ok) return status;
  c.type = static_cast<MessageType>(h.type);
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
  if (payload.size() < kStatePrefix) return DecodeStatus::BadLength;
  wire::Reader r(payload);
  State st;
  st.joint_count = r.u16();
  st.flags = r.u16();
  st.tool_count = r.u16();
  const std::uint16_t reserved = r.u16();
  st.actuations = r.u32();
  st.actuation_request = r.u32();
  if (!validJointCount(st.joint_count)) return DecodeStatus::BadLength;
  if (!validToolCount(st.tool_count)) return DecodeStatus::BadValue;
  if (payload.size() != kStatePrefix + 8 * std::size_t{st.joint_count} + kStateBytesPerTool * st.tool_count)
    return DecodeStatus::BadLength;
  if (reserved != 0 || !validFlags(st.flags, st.tool_count)) return DecodeStatus::BadValue;
  for (std::size_t i = 0; i < st.joint_count; ++i) st.joints[i] = r.f64();
  if (!wire::allFinite(std::span<const double>(st.joints.data(), st.joint_count))) return DecodeStatus::NonFinite;
  for (std::size_t t = 0; t < st.tool_count; ++t) {
    if (const DecodeStatus s = readPose(r, st.tools[t].pose); s != DecodeStatus::Ok) return s;
    for (double& v : st.tools[t].wrench) v = r.f64();
    if (!wire::allFinite(st.tools[t].wrench)) return DecodeStatus::NonFinite;
  }
  out = st;
  header = h;
  return DecodeStatus::Ok;
}

}  // namespace cobra::bridges::isur
