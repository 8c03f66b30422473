#pragma once
/// @file
/// A cyclic process-data bus to N CiA 402 drives (the thesis' EtherCAT with CoE, §6.2.1): each
/// cycle the master writes one output image per slave (RxPDO: controlword, mode, targets) and
/// reads one input image per slave (TxPDO: statusword, mode display, actual values). Values are
/// joint-side SI units; a backend for real drives converts to and from encoder counts and rated
/// torque per mille with the slave's scaling. Backends: the simulated Puma 260 of cobra::sim
/// (sim/puma260_ethercat_bus.hpp); a SOEM backend for the real drives would implement the same
/// interface. A driver finds its backend by name in core::BackendRegistry<Cia402Bus>.

#include <cstdint>
#include <span>
#include <string>

#include "cobra/fieldbus/cia402.hpp"

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
  LinkDown,   ///< the frame did not come back or no device answers: inputs are stale
  /// The frame came back with another working counter than expected: at least one slave did not
  /// process its datagram, so neither the inputs nor the slaves' outputs can be trusted this cycle
  /// (Cia402Bus::workingCounter says which counters).
  WorkingCounterMismatch,
};

/// The EtherCAT working counter of a cycle: what the master expected (every slave processed the
/// datagram) and what came back.
struct WorkingCounter {
  int expected = 0;
  int received = 0;
};

/// The bus. `exchange` is real-time safe in every backend: no allocation, no blocking beyond the
/// frame's round trip.
class Cia402Bus {
 public:
  static constexpr const char* kBackendKind = "CiA 402 (EtherCAT) bus";  ///< for core::BackendRegistry
  virtual ~Cia402Bus() = default;
  virtual int slaveCount() const noexcept = 0;
  /// A line per slave for logs and introspection (not real-time).
  virtual std::string describeSlave(int index) const = 0;
  /// One cycle: `outputs` go to the slaves, `inputs` receive what the slaves sent back. A bus runs
  /// on its own clock (the wall clock, or the simulated world's): the master's cycle is its own.
  virtual BusStatus exchange(std::span<const Cia402Outputs> outputs, std::span<Cia402Inputs> inputs) noexcept = 0;
  /// The working counter of the last exchange (both 0 for a backend without one).
  virtual WorkingCounter workingCounter() const noexcept { return {}; }
};

}  // namespace cobra::fieldbus
