#include "cobra/fieldbus/ftsens_codec.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::fieldbus {
namespace {

constexpr std::uint32_t kForceType = 0xA, kTorqueType = 0xB;

std::uint8_t checksum(std::uint32_t id, const std::array<std::uint8_t, 8>& data) noexcept {
  unsigned sum = id & 0xFFU;
  for (int i = 0; i < 7; ++i) sum += data[static_cast<std::size_t>(i)];
  return static_cast<std::uint8_t>(~sum & 0xFFU);
}

/// Counts of `value` at `lsb`, clipped to int16; sets `clipped`.
std::int16_t toCounts(double value, double lsb, bool& clipped) noexcept {
  double counts = std::nearbyint(value / lsb);
  if (!std::isfinite(counts) || counts > 32767.0 || counts < -32768.0) {
    clipped = true;
    counts = std::isnan(counts) ? 0.0 : (counts > 0 ? 32767.0 : -32768.0);
  }
  return static_cast<std::int16_t>(counts);
}

void putChannels(std::uint32_t id, const double (&values)[3], const double (&lsb)[3], std::uint8_t sequence,
                 CanFrame& frame, bool& clipped) noexcept {
  frame = CanFrame{};
  frame.id = id;
  frame.length = 8;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto raw = static_cast<std::uint16_t>(toCounts(values[i], lsb[i], clipped));
    frame.data[2 * i] = static_cast<std::uint8_t>(raw & 0xFFU);
    frame.data[2 * i + 1] = static_cast<std::uint8_t>(raw >> 8);
  }
  frame.data[6] = sequence;
  frame.data[7] = checksum(id, frame.data);
}

KDL::Vector getChannels(const CanFrame& frame, double lsb_x, double lsb_y, double lsb_z) noexcept {
  const auto channel = [&](std::size_t i) {
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(frame.data[2 * i] | (frame.data[2 * i + 1] << 8)));
  };
  return {channel(0) * lsb_x, channel(1) * lsb_y, channel(2) * lsb_z};
}

void requirePositive(const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(std::string("FTSens codec: ") + parameter + " = " + std::to_string(value) + " " + unit +
                                ", expected > 0");
  }
}

}  // namespace

void validate(const FtSensCodecConfig& c) {
  if (c.address < 0 || c.address > 15) {
    throw std::invalid_argument("FTSens codec: address = " + std::to_string(c.address) +
                                ", expected 0-15 (4 bits of the CAN identifier)");
  }
  requirePositive("force_lsb", c.force_lsb, "N");
  requirePositive("torque_xy_lsb", c.torque_xy_lsb, "N*m");
  requirePositive("torque_z_lsb", c.torque_z_lsb, "N*m");
}

std::uint32_t ftSensForceId(int address) noexcept {
  return 0x300U + (static_cast<std::uint32_t>(address) << 4) + kForceType;
}
std::uint32_t ftSensTorqueId(int address) noexcept {
  return 0x300U + (static_cast<std::uint32_t>(address) << 4) + kTorqueType;
}
std::uint32_t ftSensCommandId(int address) noexcept { return 0x200U + (static_cast<std::uint32_t>(address) << 4); }

bool encodeFtSens(const FtSensCodecConfig& c, const KDL::Wrench& w, std::uint8_t sequence, CanFrame& force_frame,
                  CanFrame& torque_frame) noexcept {
  bool clipped = false;
  const double force[3] = {w.force.x(), w.force.y(), w.force.z()};
  const double torque[3] = {w.torque.x(), w.torque.y(), w.torque.z()};
  const double force_lsb[3] = {c.force_lsb, c.force_lsb, c.force_lsb};
  const double torque_lsb[3] = {c.torque_xy_lsb, c.torque_xy_lsb, c.torque_z_lsb};
  putChannels(ftSensForceId(c.address), force, force_lsb, sequence, force_frame, clipped);
  putChannels(ftSensTorqueId(c.address), torque, torque_lsb, sequence, torque_frame, clipped);
  return clipped;
}

CanFrame ftSensStreamCommand(const FtSensCodecConfig& c, std::uint8_t period_ms) noexcept {
  CanFrame frame;
  frame.id = ftSensCommandId(c.address);
  frame.length = 2;
  frame.data[0] = kFtSensSetPeriodCommand;
  frame.data[1] = period_ms;
  return frame;
}

FtSensDecoder::FtSensDecoder(const FtSensCodecConfig& config) : config_(config) { validate(config_); }

FtSensFrameResult FtSensDecoder::push(const CanFrame& frame) noexcept {
  const bool force = frame.id == ftSensForceId(config_.address);
  const bool torque = frame.id == ftSensTorqueId(config_.address);
  if (!force && !torque) return FtSensFrameResult::Foreign;
  if (frame.extended || frame.length != 8 || frame.data[7] != checksum(frame.id, frame.data)) {
    ++garbled_;
    return FtSensFrameResult::Garbled;
  }
  const std::uint8_t sequence = frame.data[6];
  if (force) {
    const bool replaced = pending_;
    pending_force_ = getChannels(frame, config_.force_lsb, config_.force_lsb, config_.force_lsb);
    pending_sequence_ = sequence;
    pending_ = true;
    if (replaced) {
      ++unpaired_;
      return FtSensFrameResult::Unpaired;
    }
    return FtSensFrameResult::Half;
  }
  if (!pending_ || pending_sequence_ != sequence) {
    pending_ = false;
    ++unpaired_;
    return FtSensFrameResult::Unpaired;
  }
  pending_ = false;
  wrench_ = KDL::Wrench(pending_force_,
                        getChannels(frame, config_.torque_xy_lsb, config_.torque_xy_lsb, config_.torque_z_lsb));
  if (have_sample_) lost_ += static_cast<std::uint8_t>(sequence - last_sequence_ - 1);
  last_sequence_ = sequence;
  have_sample_ = true;
  ++samples_;
  return FtSensFrameResult::Sample;
}

}  // namespace cobra::fieldbus
