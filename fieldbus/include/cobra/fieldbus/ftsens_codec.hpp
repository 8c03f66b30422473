#pragma once
/// @file
/// CAN frames of the IIT FTSens force/torque sensor (thesis §6.1.2: six 16-bit channels, up to
/// 1000 messages/s, CAN 2.0B at 1 Mbit/s).
///
/// ASSUMPTION: the frame layout below is cobra's own. The thesis gives no protocol; it is
/// modelled after the periodic analog-sensor messages of the iCub CAN protocol the FTSens comes
/// from (a force frame and a torque frame per sample, the board address in the identifier), but
/// it has not been checked against IIT's documentation. Replace the codec, not the driver, when
/// the real layout is known.
///
/// Sensor -> host, one sample = two 8-byte frames with 11-bit identifiers:
/// | identifier                      | bytes 0-1 | bytes 2-3 | bytes 4-5 | byte 6   | byte 7   |
/// |---------------------------------|-----------|-----------|-----------|----------|----------|
/// | 0x300 + (address << 4) + 0xA    | Fx        | Fy        | Fz        | sequence | checksum |
/// | 0x300 + (address << 4) + 0xB    | Tx        | Ty        | Tz        | sequence | checksum |
/// Channels are signed 16-bit little-endian counts; one count is the sensor's resolution of that
/// axis (0.25 N; 0.049, 0.049, 0.037 N·m), so the table's ranges (2000 N, 40/30 N·m) fit. The
/// sequence number (0-255, wrapping) is the same in both frames of a sample. checksum = bitwise NOT
/// of the 8-bit sum of the identifier's low byte and bytes 0-6.
///
/// Host -> sensor: identifier 0x200 + (address << 4), 2 bytes: 0x07 (set streaming period) and the
/// period in ms (1-255; 0 stops streaming).

#include <cstdint>
#include <kdl/frames.hpp>

#include "cobra/fieldbus/can_bus.hpp"

namespace cobra::fieldbus {

/// Codec parameters, checked by `validate`.
struct FtSensCodecConfig {
  int address = 0;               ///< board address on the bus, 0-15
  double force_lsb = 0.25;       ///< N per count, > 0
  double torque_xy_lsb = 0.049;  ///< N·m per count, > 0 (Tx, Ty)
  double torque_z_lsb = 0.037;   ///< N·m per count, > 0 (Tz)
};

/// @throws std::invalid_argument naming the parameter and the expected range.
void validate(const FtSensCodecConfig& config);

inline constexpr std::uint8_t kFtSensSetPeriodCommand = 0x07;
std::uint32_t ftSensForceId(int address) noexcept;
std::uint32_t ftSensTorqueId(int address) noexcept;
std::uint32_t ftSensCommandId(int address) noexcept;

/// Encodes one sample. @return true when a channel was clipped to the 16-bit range.
bool encodeFtSens(const FtSensCodecConfig& config, const KDL::Wrench& wrench, std::uint8_t sequence,
                  CanFrame& force_frame, CanFrame& torque_frame) noexcept;
/// The host's "stream every `period_ms` ms" command (0 stops).
CanFrame ftSensStreamCommand(const FtSensCodecConfig& config, std::uint8_t period_ms) noexcept;

/// What one received frame was.
enum class FtSensFrameResult {
  Sample,    ///< completed a sample: wrench() is new
  Half,      ///< the force half of a sample, waiting for its torque half
  Foreign,   ///< another identifier (another device or address): ignored, not an error
  Garbled,   ///< an FTSens identifier with a wrong length, an extended identifier or a bad checksum
  Unpaired,  ///< a torque half whose force half was lost (or a force half replaced unpaired)
};

/// Reassembles samples from frames and counts what went wrong. noexcept, no allocation.
class FtSensDecoder {
 public:
  /// @throws std::invalid_argument when the configuration is invalid.
  explicit FtSensDecoder(const FtSensCodecConfig& config);

  FtSensFrameResult push(const CanFrame& frame) noexcept;

  const KDL::Wrench& wrench() const noexcept { return wrench_; }  ///< last complete sample (N, N·m)
  std::uint64_t samples() const noexcept { return samples_; }
  std::uint64_t garbled() const noexcept { return garbled_; }
  std::uint64_t unpaired() const noexcept { return unpaired_; }
  /// Samples missing between complete ones, from the sequence numbers (a gap of more than 255
  /// samples is seen modulo 256).
  std::uint64_t lost() const noexcept { return lost_; }

 private:
  FtSensCodecConfig config_;
  KDL::Vector pending_force_;
  std::uint8_t pending_sequence_ = 0, last_sequence_ = 0;
  bool pending_ = false, have_sample_ = false;
  KDL::Wrench wrench_ = KDL::Wrench::Zero();
  std::uint64_t samples_ = 0, garbled_ = 0, unpaired_ = 0, lost_ = 0;
};

}  // namespace cobra::fieldbus
