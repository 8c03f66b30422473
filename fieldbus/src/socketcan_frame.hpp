#pragma once
// Conversion between cobra's CanFrame and Linux's struct can_frame (linux/can.h), apart from the
// socket so that a test checks it on a machine without CAN interfaces.

#include <linux/can.h>

#include <algorithm>
#include <cstring>

#include "cobra/fieldbus/can_bus.hpp"

namespace cobra::fieldbus::socketcan {

inline can_frame toLinux(const CanFrame& in) noexcept {
  can_frame out{};
  out.can_id = in.extended ? ((in.id & CAN_EFF_MASK) | CAN_EFF_FLAG) : (in.id & CAN_SFF_MASK);
  out.can_dlc = std::min<std::uint8_t>(in.length, CAN_MAX_DLEN);
  std::memcpy(out.data, in.data.data(), out.can_dlc);
  return out;
}

/// False for frames CanFrame cannot hold: error frames and remote transmission requests.
inline bool fromLinux(const can_frame& in, CanFrame& out) noexcept {
  if ((in.can_id & (CAN_ERR_FLAG | CAN_RTR_FLAG)) != 0) return false;
  out.extended = (in.can_id & CAN_EFF_FLAG) != 0;
  out.id = in.can_id & (out.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  out.length = std::min<std::uint8_t>(in.can_dlc, CAN_MAX_DLEN);
  out.data = {};
  std::memcpy(out.data.data(), in.data, out.length);
  return true;
}

}  // namespace cobra::fieldbus::socketcan
