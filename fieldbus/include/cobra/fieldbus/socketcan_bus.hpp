#pragma once
/// @file
/// The Linux SocketCAN backend of CanBus: a non-blocking raw CAN socket (PF_CAN, CAN_RAW) bound to
/// one network interface (can0, vcan0, ...). Registered by package cobra_drivers as the backend
/// scheme `socketcan` (`bus = "socketcan:can0"`).

#include <string>

#include "cobra/fieldbus/can_bus.hpp"

namespace cobra::fieldbus {

/// One raw CAN socket. `send` and `receive` are system calls on a non-blocking socket: they never
/// block and never allocate. Remote-transmission-request and error frames are not delivered by
/// `receive` (CanFrame has no field for them): it skips them.
class SocketCanBus final : public CanBus {
 public:
  /// Opens the socket and binds it to `interface`.
  /// @throws std::runtime_error "SocketCAN interface 'can0': ..." when the name is malformed, no
  /// network interface has it, or the socket cannot be opened or bound (why, from the kernel).
  explicit SocketCanBus(const std::string& interface);
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  /// False when the kernel's transmit queue is full (the frame is dropped) or the link failed.
  bool send(const CanFrame& frame) noexcept override;
  bool receive(CanFrame& frame) noexcept override;
  const std::string& interface() const noexcept { return interface_; }

 private:
  std::string interface_;
  int fd_ = -1;
};

}  // namespace cobra::fieldbus
