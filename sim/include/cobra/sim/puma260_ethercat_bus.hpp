#pragma once
/// @file
/// Six simulated Elmo drives on a simulated Puma 260 (sim::Puma260Arm) behind the cyclic process
/// data of fieldbus::Cia402Bus (thesis §6.2.1, EtherCAT with CoE). The host side is what the
/// Puma 260 EtherCAT master uses; the world side steps the arm and injects faults. See
/// device_link.hpp for when each side sees the other's process data.

#include <array>
#include <string>

#include "cobra/fieldbus/cia402_bus.hpp"
#include "cobra/sim/device_link.hpp"
#include "cobra/sim/puma260_arm.hpp"

namespace cobra::sim {

class Puma260EtherCatBus final : public fieldbus::Cia402Bus {
 public:
  using Outputs = std::array<fieldbus::Cia402Outputs, 6>;
  using Inputs = std::array<fieldbus::Cia402Inputs, 6>;

  /// @param initial joint positions at power-on (rad)
  /// @throws std::invalid_argument when the model is invalid.
  explicit Puma260EtherCatBus(const Puma260ArmModel& model = Puma260ArmModel::defaults(),
                              const std::array<double, 6>& initial = {});

  /// Host side.
  int slaveCount() const noexcept override { return 6; }
  /// Host side: the slave as the host saw it in its last exchange (state, error code, position).
  std::string describeSlave(int index) const override;
  /// Host side: hands `outputs` to the drives (they take them at the world's next step) and
  /// returns the newest inputs the host may see. LinkDown when the world side detached.
  fieldbus::BusStatus exchange(std::span<const fieldbus::Cia402Outputs> outputs,
                               std::span<fieldbus::Cia402Inputs> inputs) noexcept override;

  /// World side: the clock and connection state. The drives' power-on inputs are visible at once.
  DeviceLink& link() noexcept { return link_; }
  /// World side: applies the newest outputs the drives may see, steps the arm by `dt` (s) and
  /// publishes the drives' inputs.
  void step(double dt) noexcept;
  /// World side: the simulated arm, for fault injection and ground truth.
  Puma260Arm& arm() noexcept { return arm_; }
  const Puma260Arm& arm() const noexcept { return arm_; }

 private:
  void publish(std::int64_t stamp) noexcept;

  DeviceLink link_;
  Puma260Arm arm_;
  StampedMailbox<Outputs> outputs_;
  StampedMailbox<Inputs> inputs_;
  Inputs seen_{};  // host side: the inputs of its last exchange
};

}  // namespace cobra::sim
