#include "cobra/sim/ftsens_can_bus.hpp"

namespace cobra::sim {

FtSensCanBus::FtSensCanBus(const ForceTorqueSensorModel& sensor, const fieldbus::FtSensCodecConfig& codec,
                           std::uint64_t seed)
    : sensor_(sensor, seed), codec_(codec) {
  fieldbus::validate(codec_);
}

bool FtSensCanBus::send(const fieldbus::CanFrame& frame) noexcept {
  const DeviceLink::Access access(link_);
  return access.up() && to_sensor_.push({frame, access.time().now});
}

bool FtSensCanBus::receive(fieldbus::CanFrame& frame) noexcept {
  const DeviceLink::Access access(link_);
  StampedFrame next;
  if (!access.up() || !to_host_.front(next) || !access.time().visible(next.stamp)) return false;
  to_host_.pop();
  frame = next.frame;
  return true;
}

void FtSensCanBus::enqueue(fieldbus::CanFrame frame, std::int64_t stamp) noexcept {
  if (garble_ > 0) {
    --garble_;
    frame.data[2] ^= 0x10U;
  }
  if (!to_host_.push({frame, stamp})) ++overruns_;
}

void FtSensCanBus::advance(double dt) noexcept {
  const LinkTime time = link_.worldTime();
  StampedFrame command;
  while (to_sensor_.front(command) && time.visible(command.stamp)) {
    to_sensor_.pop();
    const fieldbus::CanFrame& f = command.frame;
    // Frames for other nodes are ignored by this one.
    if (f.id == fieldbus::ftSensCommandId(codec_.address) && !f.extended && f.length == 2 &&
        f.data[0] == fieldbus::kFtSensSetPeriodCommand) {
      period_ = f.data[1] * 1e-3;
      since_sample_ = 0.0;
    }
  }
  if (period_ <= 0.0 || !(dt > 0.0)) return;
  since_sample_ += dt;
  while (since_sample_ + 1e-12 >= period_) {
    since_sample_ -= period_;
    const ForceTorqueReading& reading = sensor_.step(period_, truth_);
    const std::uint8_t sequence = sequence_++;
    if (silent_) continue;
    if (drop_ > 0) {
      --drop_;
      continue;
    }
    fieldbus::CanFrame force, torque;
    fieldbus::encodeFtSens(codec_, reading.wrench, sequence, force, torque);
    enqueue(force, time.now);
    enqueue(torque, time.now);
  }
}

}  // namespace cobra::sim
