#pragma once
/// @file
/// A simulated Leap Motion (sim::HandTracker) behind fieldbus::HandTrackerDevice, the interface
/// the Leap Motion driver uses. The world side takes the true hand poses and steps the tracker;
/// the host side takes frames. See device_link.hpp for when the host sees a frame.

#include <cstdint>

#include "cobra/fieldbus/hand_tracker_device.hpp"
#include "cobra/sim/device_link.hpp"
#include "cobra/sim/hand_tracker.hpp"

namespace cobra::sim {

class LeapMotionDevice final : public fieldbus::HandTrackerDevice {
 public:
  /// @throws std::invalid_argument when the model is invalid.
  explicit LeapMotionDevice(const HandTrackerModel& model, std::uint64_t seed = 0) : tracker_(model, seed) {}

  /// Host side: the newest frame the host may see, when it is newer than the last one taken.
  bool takeFrame(fieldbus::HandFrame& frame) noexcept override;

  /// World side: the clock and connection state.
  DeviceLink& link() noexcept { return link_; }
  /// World side: advances the tracker by `dt` (s) with the true hands (m, device frame; a hand
  /// not present is not above the device at all) and publishes the frame that fell due.
  void step(double dt, bool right_present, const KDL::Frame& right, bool left_present, const KDL::Frame& left) noexcept;
  const HandTracker& tracker() const noexcept { return tracker_; }

 private:
  DeviceLink link_;
  HandTracker tracker_;
  StampedMailbox<fieldbus::HandFrame> frames_;
  std::uint64_t taken_ = 0;  // host side: id of the last frame taken
};

}  // namespace cobra::sim
