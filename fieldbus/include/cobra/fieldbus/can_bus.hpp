#pragma once
/// @file
/// Classic CAN 2.0B frames (the FTSens link, thesis §6.1.2: CAN 2.0B at 1 Mbit/s) and the bus
/// interface a driver uses to send and receive them without blocking.

#include <array>
#include <cstdint>

namespace cobra::fieldbus {

/// One CAN frame: 11-bit or 29-bit identifier, 0-8 data bytes.
struct CanFrame {
  std::uint32_t id = 0;     ///< identifier (11-bit unless `extended`)
  bool extended = false;    ///< 29-bit identifier (CAN 2.0B)
  std::uint8_t length = 0;  ///< data length code, 0-8
  std::array<std::uint8_t, 8> data{};
};

/// A CAN interface. Both calls are real-time safe: they never block and never allocate. Backends:
/// SocketCanBus (socketcan_bus.hpp) and the simulated FTSens of cobra::sim; a driver finds its
/// backend by name in core::BackendRegistry<CanBus>.
class CanBus {
 public:
  static constexpr const char* kBackendKind = "CAN bus";  ///< for core::BackendRegistry
  virtual ~CanBus() = default;
  /// Queues `frame` for transmission; false when the transmit queue is full (frame dropped).
  virtual bool send(const CanFrame& frame) noexcept = 0;
  /// Takes the oldest received frame; false when none is waiting.
  virtual bool receive(CanFrame& frame) noexcept = 0;
};

}  // namespace cobra::fieldbus
