#include "cobra/sim/puma260_ethercat_bus.hpp"

#include <cstdio>

namespace cobra::sim {

Puma260EtherCatBus::Puma260EtherCatBus(const Puma260ArmModel& model, const std::array<double, 6>& initial)
    : arm_(model, initial) {
  publish(kAlwaysVisible);
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
  Outputs out;
  for (std::size_t i = 0; i < 6; ++i) out[i] = outputs[i];
  outputs_.write(out, access.time().now);
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
      Cia402Drive& d = arm_.drive(i);
      d.setControlword(o.controlword);
      d.setModeOfOperation(static_cast<Cia402Mode>(static_cast<std::int8_t>(o.mode)));
      d.setTargetPosition(o.target_position);
      d.setTargetVelocity(o.target_velocity);
      d.setTargetTorque(o.target_torque);
    }
  }
  arm_.step(dt);
  publish(time.now);
}

void Puma260EtherCatBus::publish(std::int64_t stamp) noexcept {
  Inputs in;
  for (int i = 0; i < 6; ++i) {
    const Cia402Drive& d = arm_.drive(i);
    in[static_cast<std::size_t>(i)] = {d.statusword(), static_cast<std::int8_t>(d.modeDisplay()),
                                       d.position(),   d.velocity(),
                                       d.torque(),     d.errorCode()};
  }
  inputs_.write(in, stamp);
}

}  // namespace cobra::sim
