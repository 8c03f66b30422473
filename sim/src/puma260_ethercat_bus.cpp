#include "cobra/sim/puma260_ethercat_bus.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cobra::sim {

Puma260EtherCatBus::Puma260EtherCatBus(const Puma260ArmModel& model, const std::array<double, 6>& initial)
    : Puma260EtherCatBus(std::make_unique<Puma260Arm>(model, initial)) {}

Puma260EtherCatBus::Puma260EtherCatBus(std::unique_ptr<Puma260Plant> plant) : arm_(std::move(plant)) {
  if (!arm_) throw std::invalid_argument("Puma 260 EtherCAT bus: no arm to drive (null plant)");
  publish(kAlwaysVisible);
}

void Puma260EtherCatBus::setEncoderNoise(double std_dev, std::uint64_t seed) {
  if (!std::isfinite(std_dev) || std_dev < 0.0) {
    throw std::invalid_argument("Puma 260 EtherCAT bus: encoder noise = " + std::to_string(std_dev) +
                                " rad, expected >= 0 (a standard deviation)");
  }
  encoder_noise_ = std_dev;
  noise_.seed(seed);
}

std::string Puma260EtherCatBus::describeSlave(int index) const {
  if (index < 0 || index >= slaveCount()) {
    return "no slave " + std::to_string(index) + " (the bus has slaves 0-" + std::to_string(slaveCount() - 1) + ")";
  }
  const fieldbus::Cia402Inputs& in = seen_[static_cast<std::size_t>(index)];
  char line[160];
  std::snprintf(line, sizeof line,
                "slave %d: simulated Elmo Gold Solo Whistle (CiA 402), %s, statusword 0x%04X, "
                "error 0x%04X, position %.6f rad",
                index, fieldbus::cia402::toString(fieldbus::cia402::decodeStatusword(in.statusword)), in.statusword,
                in.error_code, in.position);
  return line;
}

fieldbus::BusStatus Puma260EtherCatBus::exchange(std::span<const fieldbus::Cia402Outputs> outputs,
                                                 std::span<fieldbus::Cia402Inputs> inputs) noexcept {
  if (outputs.size() != 6 || inputs.size() != 6) return fieldbus::BusStatus::WrongSize;
  const DeviceLink::Access access(link_);
  if (!access.up()) return fieldbus::BusStatus::LinkDown;
  // An injected working-counter fault: the last slave lets the frame pass without processing its
  // datagram (it keeps its previous outputs, contributes nothing to the counter).
  int pending = wrong_counter_cycles_.load();
  while (pending > 0 && !wrong_counter_cycles_.compare_exchange_weak(pending, pending - 1)) {
  }
  const bool skipped = pending > 0;
  for (std::size_t i = 0; i < (skipped ? 5U : 6U); ++i) sent_[i] = outputs[i];
  outputs_.write(sent_, access.time().now);
  working_counter_ = {kExpectedWorkingCounter, kExpectedWorkingCounter - (skipped ? 3 : 0)};
  if (skipped) return fieldbus::BusStatus::WorkingCounterMismatch;
  const Inputs* in = inputs_.newest(access.time());
  if (in == nullptr) return fieldbus::BusStatus::LinkDown;
  seen_ = *in;
  for (std::size_t i = 0; i < 6; ++i) inputs[i] = seen_[i];
  return fieldbus::BusStatus::Ok;
}

void Puma260EtherCatBus::step(double dt) noexcept {
  const LinkTime time = link_.worldTime();
  if (const Outputs* out = outputs_.newest(time)) {
    for (int i = 0; i < 6; ++i) {
      const fieldbus::Cia402Outputs& o = (*out)[static_cast<std::size_t>(i)];
      Cia402Drive& d = arm_->drive(i);
      d.setControlword(o.controlword);
      d.setModeOfOperation(static_cast<Cia402Mode>(static_cast<std::int8_t>(o.mode)));
      d.setTargetPosition(o.target_position);
      d.setTargetVelocity(o.target_velocity);
      d.setTargetTorque(o.target_torque);
    }
  }
  arm_->step(dt);
  publish(time.now);
}

void Puma260EtherCatBus::publish(std::int64_t stamp) noexcept {
  Inputs in;
  for (int i = 0; i < 6; ++i) {
    const Cia402Drive& d = arm_->drive(i);
    const double noise = encoder_noise_ > 0.0 ? encoder_noise_ * noise_.sample() : 0.0;
    in[static_cast<std::size_t>(i)] = {d.statusword(), static_cast<std::int8_t>(d.modeDisplay()),
                                       d.position() + noise, d.velocity(),
                                       d.torque(),     d.errorCode()};
  }
  inputs_.write(in, stamp);
}

}  // namespace cobra::sim
