// libFuzzer target: arbitrary byte streams cut into CAN frames (identifier, flags, length, data)
// fed to the FTSens decoder. It must never crash, never read past a frame, and keep its counters
// consistent: every decoded wrench is finite and within the 16-bit range of the channels.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "cobra/fieldbus/ftsens_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cobra::fieldbus::FtSensCodecConfig config;
  config.address = size > 0 ? data[0] & 0x0F : 0;
  cobra::fieldbus::FtSensDecoder decoder(config);
  constexpr std::size_t kRecord = 12;  // 2 bytes id, 1 flags, 1 length, 8 data
  for (std::size_t at = 1; at + kRecord <= size; at += kRecord) {
    cobra::fieldbus::CanFrame frame;
    // Bias identifiers towards the sensor's own so that the checksum and pairing paths run.
    frame.id = static_cast<std::uint32_t>(data[at] & 0x01 ? (0x300U + (config.address << 4) + 0xA + (data[at + 1] & 1))
                                                          : (data[at] | (data[at + 1] << 8)) & 0x7FF);
    frame.extended = data[at + 2] & 0x80;
    frame.length = static_cast<std::uint8_t>(data[at + 3] % 16);  // a bad DLC (> 8) must be rejected too
    for (std::size_t i = 0; i < 8; ++i) frame.data[i] = data[at + 4 + i];
    (void)decoder.push(frame);
    const KDL::Wrench& w = decoder.wrench();
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(w.force[k]) || std::abs(w.force[k]) > 32768 * config.force_lsb) std::abort();
      if (!std::isfinite(w.torque[k]) || std::abs(w.torque[k]) > 32768 * config.torque_xy_lsb) std::abort();
    }
  }
  return 0;
}
