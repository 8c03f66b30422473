#include "cobra/fieldbus/simulated_ftsens.hpp"

namespace cobra::fieldbus {

SimulatedFtSensBus::SimulatedFtSensBus(const sim::ForceTorqueSensorModel& sensor, const FtSensCodecConfig& codec,
                                       std::uint64_t seed)
    : sensor_(sensor, seed), codec_(codec) {
  validate(codec_);
}

bool SimulatedFtSensBus::send(const CanFrame& frame) noexcept {
  if (frame.id == ftSensCommandId(codec_.address) && !frame.extended && frame.length == 2 &&
      frame.data[0] == kFtSensSetPeriodCommand) {
    period_ = frame.data[1] * 1e-3;
    since_sample_ = 0.0;
  }
  return true;  // the bus takes every frame; frames for other nodes are ignored by this one
}

bool SimulatedFtSensBus::receive(CanFrame& frame) noexcept {
  if (size_ == 0) return false;
  frame = queue_[head_];
  head_ = (head_ + 1) % queue_.size();
  --size_;
  return true;
}

void SimulatedFtSensBus::enqueue(CanFrame frame) noexcept {
  if (garble_ > 0) {
    --garble_;
    frame.data[2] ^= 0x10U;
  }
  if (size_ == queue_.size()) {  // overrun: the oldest frame is lost
    head_ = (head_ + 1) % queue_.size();
    --size_;
    ++overruns_;
  }
  queue_[(head_ + size_) % queue_.size()] = frame;
  ++size_;
}

void SimulatedFtSensBus::advance(double dt) noexcept {
  if (period_ <= 0.0 || !(dt > 0.0)) return;
  since_sample_ += dt;
  while (since_sample_ + 1e-12 >= period_) {
    since_sample_ -= period_;
    const sim::ForceTorqueReading& reading = sensor_.step(period_, truth_);
    const std::uint8_t sequence = sequence_++;
    if (silent_) continue;
    if (drop_ > 0) {
      --drop_;
      continue;
    }
    CanFrame force, torque;
    encodeFtSens(codec_, reading.wrench, sequence, force, torque);
    enqueue(force);
    enqueue(torque);
  }
}

}  // namespace cobra::fieldbus
