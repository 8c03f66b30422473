#include "cobra/fieldbus/cia402_bus.hpp"

#include <cstdio>

namespace cobra::fieldbus {

SimulatedPuma260Bus::SimulatedPuma260Bus(const sim::Puma260ArmModel& model, const std::array<double, 6>& initial)
    : arm_(model, initial) {}

std::string SimulatedPuma260Bus::describeSlave(int index) const {
  if (index < 0 || index >= slaveCount()) {
    return "no slave " + std::to_string(index) + " (the bus has slaves 0-" + std::to_string(slaveCount() - 1) + ")";
  }
  const sim::Cia402Drive& d = arm_.drive(index);
  char line[160];
  std::snprintf(line, sizeof line,
                "slave %d: simulated Elmo Gold Solo Whistle (CiA 402), %s, statusword 0x%04X, "
                "error 0x%04X, position %.6f rad",
                index, sim::toString(d.state()), d.statusword(), d.errorCode(), d.position());
  return line;
}

BusStatus SimulatedPuma260Bus::exchange(std::span<const Cia402Outputs> outputs, std::span<Cia402Inputs> inputs,
                                        double cycle_time) noexcept {
  if (outputs.size() != 6 || inputs.size() != 6) return BusStatus::WrongSize;
  for (int i = 0; i < 6; ++i) {
    const Cia402Outputs& o = outputs[static_cast<std::size_t>(i)];
    sim::Cia402Drive& d = arm_.drive(i);
    d.setControlword(o.controlword);
    d.setModeOfOperation(static_cast<sim::Cia402Mode>(static_cast<std::int8_t>(o.mode)));
    d.setTargetPosition(o.target_position);
    d.setTargetVelocity(o.target_velocity);
    d.setTargetTorque(o.target_torque);
  }
  arm_.step(cycle_time);
  for (int i = 0; i < 6; ++i) {
    const sim::Cia402Drive& d = arm_.drive(i);
    inputs[static_cast<std::size_t>(i)] = {d.statusword(), static_cast<std::int8_t>(d.modeDisplay()),
                                           d.position(),   d.velocity(),
                                           d.torque(),     d.errorCode()};
  }
  return BusStatus::Ok;
}

}  // namespace cobra::fieldbus
