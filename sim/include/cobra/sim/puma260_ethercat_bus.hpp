#pragma once
/// @file
/// Six simulated Elmo drives on a simulated Puma 260 (a sim::Puma260Plant: the analytic
/// sim::Puma260Arm or the MuJoCo world's sim::MujocoPuma260Arm) behind the cyclic process data of
/// fieldbus::Cia402Bus (thesis §6.2.1, EtherCAT with CoE). The host side is what the Puma 260
/// EtherCAT master uses; the world side steps the arm and injects faults (drive faults, frames
/// with a wrong working counter). See device_link.hpp for when each side sees the other's process
/// data.

#include <array>
#include <atomic>
#include <memory>
#include <string>

#include "cobra/fieldbus/cia402_bus.hpp"
#include "cobra/sim/device_link.hpp"
#include "cobra/sim/puma260_arm.hpp"
#include "cobra/sim/gaussian_noise.hpp"

namespace cobra::sim {

class Puma260EtherCatBus final : public fieldbus::Cia402Bus {
 public:
  using Outputs = std::array<fieldbus::Cia402Outputs, 6>;
  using Inputs = std::array<fieldbus::Cia402Inputs, 6>;

  /// @param initial joint positions at power-on (rad)
  /// @throws std::invalid_argument when the model is invalid.
  explicit Puma260EtherCatBus(const Puma260ArmModel& model = Puma260ArmModel::defaults(),
                              const std::array<double, 6>& initial = {});
  /// The drives of `plant` (not null).
  /// @throws std::invalid_argument when `plant` is null.
  explicit Puma260EtherCatBus(std::unique_ptr<Puma260Plant> plant);

  /// The working counter of a cycle in which every slave processed its datagram: 3 per slave
  /// (an EtherCAT LRW datagram counts +1 for the read, +2 for the write in each slave).
  static constexpr int kExpectedWorkingCounter = 3 * 6;

  /// Host side.
  int slaveCount() const noexcept override { return 6; }
  /// Host side: the slave as the host saw it in its last exchange (state, error code, position).
  std::string describeSlave(int index) const override;
  /// Host side: hands `outputs` to the drives (they take them at the world's next step) and
  /// returns the newest inputs the host may see. LinkDown when the world side detached;
  /// WorkingCounterMismatch while an injected working-counter fault lasts (the last slave did not
  /// process the frame: it keeps its previous outputs and the host gets no new inputs).
  fieldbus::BusStatus exchange(std::span<const fieldbus::Cia402Outputs> outputs,
                               std::span<fieldbus::Cia402Inputs> inputs) noexcept override;
  /// Host side: the working counter of the last exchange.
  fieldbus::WorkingCounter workingCounter() const noexcept override { return working_counter_; }

  /// World side: the clock and connection state. The drives' power-on inputs are visible at once.
  DeviceLink& link() noexcept { return link_; }
  /// World side: applies the newest outputs the drives may see, steps the arm by `dt` (s) and
  /// publishes the drives' inputs.
  void step(double dt) noexcept;
  /// World side: the simulated arm, for fault injection and ground truth.
  Puma260Plant& arm() noexcept { return *arm_; }
  const Puma260Plant& arm() const noexcept { return *arm_; }
  /// World side: Gaussian noise of `std_dev` rad (>= 0; 0 = none, the default) on the joint
  /// positions the drives report (their own loops see the true position), from `seed`.
  /// @throws std::invalid_argument for a negative or non-finite std_dev.
  void setEncoderNoise(double std_dev, std::uint64_t seed);
  /// World side (any thread): the next `cycles` exchanges (>= 0) see a working-counter mismatch.
  void injectWorkingCounterFault(int cycles) noexcept { wrong_counter_cycles_.store(cycles < 0 ? 0 : cycles); }

 private:
  void publish(std::int64_t stamp) noexcept;

  DeviceLink link_;
  std::unique_ptr<Puma260Plant> arm_;
  std::atomic<int> wrong_counter_cycles_{0};
  double encoder_noise_ = 0.0;  // rad
  GaussianNoise noise_;
  fieldbus::WorkingCounter working_counter_{kExpectedWorkingCounter, kExpectedWorkingCounter};  // host side
  StampedMailbox<Outputs> outputs_;
  StampedMailbox<Inputs> inputs_;
  Inputs seen_{};  // host side: the inputs of its last exchange
  Outputs sent_{};  // host side: the outputs the slaves hold
};

}  // namespace cobra::sim
