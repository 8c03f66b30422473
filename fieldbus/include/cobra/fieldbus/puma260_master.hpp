#pragma once
/// @file
/// The logic of the Puma 260 EtherCAT master (thesis §6.2.1, Fig. 6.4) without the runtime: the
/// component states NotInitialized -> Initialized -> MovingToReady -> ReadyPosition ->
/// MovingToNest -> NestPosition / Operative, plus Fault; the per-slave CiA 402 sequencing; the
/// joint moves to the nest and ready positions; and the position / velocity / torque command
/// paths in Operative. It drives any Cia402Bus with six slaves. Joint-side SI units.

#include <array>
#include <cstdint>

#include "cobra/fieldbus/cia402.hpp"
#include "cobra/fieldbus/cia402_bus.hpp"

namespace cobra::fieldbus {

using JointVector = std::array<double, 6>;

/// The states of Fig. 6.4, plus Fault (a drive reported a fault, the bus failed or a cycle came
/// back with a wrong working counter).
enum class MasterState {
  NotInitialized,
  Initialized,
  MovingToNest,
  NestPosition,
  MovingToReady,
  ReadyPosition,
  Operative,
  Fault
};
/// "NotInitialized", "Initialized", ... (the names of Fig. 6.4 without spaces).
const char* toString(MasterState state) noexcept;

enum class ControlMode { Position, Velocity, Torque };
/// Parses "position", "velocity" or "torque". @return false for anything else.
bool parseControlMode(const char* text, ControlMode& out) noexcept;

/// Configuration, checked by `validate`.
struct Puma260MasterConfig {
  ControlMode control_mode = ControlMode::Position;
  JointVector nest{};                ///< rad: the nest (encoder initialisation) position
  JointVector ready{};               ///< rad: the ready position
  double move_speed = 0.5;           ///< rad/s, > 0: peak joint speed of the nest/ready moves
  double position_tolerance = 2e-3;  ///< rad, > 0: a move ends when every joint is this close
  JointVector lower{}, upper{};      ///< rad: joint limits; position targets are clamped into them
  double max_velocity = 2.0;         ///< rad/s, > 0: velocity-mode commands are clamped to it
  double max_torque = 20.0;          ///< N·m, > 0: torque-mode commands are clamped to it
};

/// @throws std::invalid_argument naming the parameter and joint ("ready[2] = 3.2 rad is outside
/// the joint limits [-3.93, 0.785] rad", ...).
void validate(const Puma260MasterConfig& config);

/// Bits of the value `step` returns: what happened in that cycle.
namespace master_event {
inline constexpr std::uint32_t kInitialized = 1U << 0;
inline constexpr std::uint32_t kReadyReached = 1U << 1;
inline constexpr std::uint32_t kNestReached = 1U << 2;
inline constexpr std::uint32_t kOperative = 1U << 3;
inline constexpr std::uint32_t kDriveFault = 1U << 4;
inline constexpr std::uint32_t kFaultReset = 1U << 5;
inline constexpr std::uint32_t kBusError = 1U << 6;
inline constexpr std::uint32_t kCommandClamped = 1U << 7;  ///< an Operative command was clamped (first cycle of it)
/// The cycle's working counter was not the expected one (Puma260Master::workingCounter): a slave
/// did not process its datagram. Safe state as for a bus error: Fault, every drive quick-stops.
inline constexpr std::uint32_t kWorkingCounterMismatch = 1U << 8;
}  // namespace master_event

enum class Request { Nest, Ready, Operative, FaultReset };

/// Desired joint values for Operative; `*_valid` false until something was received.
struct JointCommands {
  JointVector position{}, velocity{}, torque{};  ///< rad, rad/s, N·m
  bool position_valid = false, velocity_valid = false, torque_valid = false;
};

/// The master. `request` and `step` are noexcept and allocate nothing.
class Puma260Master {
 public:
  /// @throws std::invalid_argument when the configuration is invalid or the bus does not have six slaves.
  Puma260Master(const Puma260MasterConfig& config, Cia402Bus& bus);

  /// Asks for a state change; false (nothing changes) when `request` is not allowed now: Ready from
  /// Initialized, NestPosition, ReadyPosition or Operative; Nest and Operative from ReadyPosition;
  /// FaultReset from Fault.
  bool request(Request request) noexcept;
  /// One bus cycle of `dt` seconds with the Operative commands `commands`. @return master_event bits.
  std::uint32_t step(double dt, const JointCommands& commands) noexcept;

  MasterState state() const noexcept { return state_; }
  const JointVector& position() const noexcept { return position_; }  ///< rad, measured
  const JointVector& velocity() const noexcept { return velocity_; }  ///< rad/s, measured
  const JointVector& torque() const noexcept { return torque_; }      ///< N·m, measured
  /// Slave that raised the last fault (-1: none or the bus) and its error code (object 0x603F).
  int faultSlave() const noexcept { return fault_slave_; }
  std::uint16_t faultCode() const noexcept { return fault_code_; }
  /// The working counter of the last cycle that did not match (both 0: none yet).
  WorkingCounter workingCounterFault() const noexcept { return working_counter_fault_; }
  const cia402::DriveSequencer& sequencer(int slave) const noexcept {
    return sequencers_[static_cast<std::size_t>(slave)];
  }
  const Puma260MasterConfig& config() const noexcept { return config_; }

 private:
  void startMove(const JointVector& goal, MasterState moving) noexcept;
  void setGoal(cia402::Goal goal) noexcept;
  bool allAtGoal() const noexcept;
  void fillTargets(const JointCommands& commands, std::uint32_t& events) noexcept;

  Puma260MasterConfig config_;
  Cia402Bus& bus_;
  MasterState state_ = MasterState::NotInitialized;
  std::array<cia402::DriveSequencer, 6> sequencers_{};
  std::array<Cia402Outputs, 6> outputs_{};
  std::array<Cia402Inputs, 6> inputs_{};
  JointVector position_{}, velocity_{}, torque_{};
  JointVector hold_{};  // rad: position target outside Operative
  JointVector move_start_{}, move_goal_{};
  double move_time_ = 0.0, move_duration_ = 0.0;  // s
  bool clamped_ = false, operative_pending_ = false, recovering_ = false;
  int fault_slave_ = -1;
  std::uint16_t fault_code_ = 0;
  WorkingCounter working_counter_fault_{};
};

}  // namespace cobra::fieldbus
