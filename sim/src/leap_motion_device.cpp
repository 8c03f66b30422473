#include "cobra/sim/leap_motion_device.hpp"

namespace cobra::sim {

bool LeapMotionDevice::takeFrame(fieldbus::HandFrame& frame) noexcept {
  const DeviceLink::Access access(link_);
  if (!access.up()) return false;
  const fieldbus::HandFrame* newest = frames_.newest(access.time());
  if (newest == nullptr || newest->id <= taken_) return false;
  taken_ = newest->id;
  frame = *newest;
  return true;
}

void LeapMotionDevice::step(double dt, bool right_present, const KDL::Frame& right, bool left_present,
                            const KDL::Frame& left) noexcept {
  if (tracker_.step(dt, right_present, right, left_present, left)) frames_.write(tracker_.frame(), link_.worldTime().now);
}

}  // namespace cobra::sim
