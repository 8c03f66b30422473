#pragma once
/// @file
/// An optical hand tracker as a driver sees it (the Leap Motion of thesis §5.3.3 and §5.4.4: a
/// USB device that delivers frames of tracked hands at about 200 fps). Backends: the simulated
/// tracker of cobra::sim (sim/hand_tracker_device.hpp); a Leap Motion SDK backend would implement
/// the same interface. A driver finds its backend by name in core::BackendRegistry<HandTrackerDevice>.
///
/// Device frame L: origin at the device centre, z up out of the device, x along its long side;
/// metres and radians.

#include <cstdint>
#include <kdl/frames.hpp>

namespace cobra::fieldbus {

/// One tracked hand in one frame: `valid` false when the hand was not seen (its pose then keeps
/// the previous value and means nothing).
struct TrackedHand {
  bool valid = false;
  KDL::Frame pose;  ///< m, frame L
};

/// One device frame.
struct HandFrame {
  std::uint64_t id = 0;  ///< counts frames from 1; 0 = no frame yet
  TrackedHand right, left;
};

/// The device.
class HandTrackerDevice {
 public:
  static constexpr const char* kBackendKind = "hand tracker";  ///< for core::BackendRegistry
  virtual ~HandTrackerDevice() = default;
  /// Takes the newest frame the device delivered since the last call into `frame`; false (frame
  /// untouched) when none came or the device is not connected. Real-time safe: noexcept, no
  /// allocation, never blocks.
  virtual bool takeFrame(HandFrame& frame) noexcept = 0;
};

}  // namespace cobra::fieldbus
