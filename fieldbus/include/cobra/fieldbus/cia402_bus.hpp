#pragma once
/// @file
/// A cyclic process-data bus to N CiA 402 drives (the thesis' EtherCAT with CoE, §6.2.1): each
/// cycle the master writes one output image per slave (RxPDO: controlword, mode, targets) and
/// reads one input image per slave (TxPDO: statusword, mode display, actual values). Values are
/// joint-side SI units; a backend for real drives converts to and from encoder counts and rated
/// torque per mille with the slave's scaling. `SimulatedPuma260Bus` is the backend over
/// cobra::sim's Puma 260; a SOEM backend for the real drives would implement the same interface.

#include <cstdint>
#include <span>
#include <string>

#include "cobra/fieldbus/cia402.hpp"
#include "cobra/sim/puma260_arm.hpp"

namespace cobra::fieldbus {

/// Master -> slave process data (objects 0x6040, 0x6060, 0x607A, 0x60FF, 0x6071).
struct Cia402Outputs {
  std::uint16_t controlword = 0;
  cia402::Mode mode = cia402::Mode::CyclicPosition;
  double target_position = 0.0;  ///< rad
  double target_velocity = 0.0;  ///< rad/s
  double target_torque = 0.0;    ///< N·m
};

/// Slave -> master process data (objects 0x6041, 0x6061, 0x6064, 0x606C, 0x6077, 0x603F).
struct Cia402Inputs {
  std::uint16_t statusword = 0;
  std::int8_t mode_display = 0;
  double position = 0.0;  ///< rad
  double velocity = 0.0;  ///< rad/s
  double torque = 0.0;    ///< N·m
  std::uint16_t error_code = 0;
};

/// Outcome of one bus cycle.
enum class BusStatus {
  Ok,
  WrongSize,  ///< the spans do not have slaveCount() elements: nothing was exchanged
  LinkDown,   ///< the frame did not come back (real bus): inputs are stale
};

/// The bus. `exchange` is real-time safe in every backend: no allocation, no blocking beyond the
/// frame's round trip.
class Cia402Bus {
 public:
  virtual ~Cia402Bus() = default;
  virtual int slaveCount() const noexcept = 0;
  /// A line per slave for logs and introspection (not real-time).
  virtual std::string describeSlave(int index) const = 0;
  /// One cycle. @param cycle_time s since the previous cycle: a simulated bus advances its world
  /// by it; a real bus runs on the wall clock and ignores it.
  virtual BusStatus exchange(std::span<const Cia402Outputs> outputs, std::span<Cia402Inputs> inputs,
                             double cycle_time) noexcept = 0;
};

/// Six simulated Elmo drives on a simulated Puma 260 (sim::Puma260Arm).
class SimulatedPuma260Bus final : public Cia402Bus {
 public:
  /// @throws std::invalid_argument when the model is invalid.
  explicit SimulatedPuma260Bus(const sim::Puma260ArmModel& model = sim::Puma260ArmModel::defaults(),
                               const std::array<double, 6>& initial = {});

  int slaveCount() const noexcept override { return 6; }
  std::string describeSlave(int index) const override;
  BusStatus exchange(std::span<const Cia402Outputs> outputs, std::span<Cia402Inputs> inputs,
                     double cycle_time) noexcept override;

  /// The simulated world, for fault injection and ground truth in tests.
  sim::Puma260Arm& arm() noexcept { return arm_; }

 private:
  sim::Puma260Arm arm_;
};

}  // namespace cobra::fieldbus
