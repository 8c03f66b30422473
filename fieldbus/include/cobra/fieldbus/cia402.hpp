#pragma once
/// @file
/// The master side of the CiA 402 drive profile (IEC 61800-7-201; the thesis' Elmo drives over
/// EtherCAT/CoE, §6.1.1, §6.2.1): decoding a statusword (object 0x6041) into the power drive
/// system state by the standard's bit-pattern table, and choosing the controlword (object 0x6040)
/// that moves a drive towards a goal one transition per bus cycle. Written from the standard, not
/// from cobra::sim's drive model, so that tests can cross-check the two.

#include <cstdint>

namespace cobra::fieldbus::cia402 {

/// Power drive system states as the master sees them; `Unknown` for a statusword that matches no
/// row of the table (a garbled or not-yet-valid process image).
enum class DeviceState {
  Unknown,
  NotReadyToSwitchOn,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
};

/// Stable name ("operation_enabled", ...; "unknown").
const char* toString(DeviceState state) noexcept;

/// Decodes bits 0-3, 5 and 6 of a statusword; the other bits (voltage enabled, remote, target
/// reached, mode-specific bits) do not change the state.
DeviceState decodeStatusword(std::uint16_t statusword) noexcept;

/// Modes of operation (object 0x6060) the master uses: cyclic synchronous position, velocity,
/// torque.
enum class Mode : std::int8_t { CyclicPosition = 8, CyclicVelocity = 9, CyclicTorque = 10 };

/// Device control commands (controlword values of the standard's command table).
namespace command {
inline constexpr std::uint16_t kDisableVoltage = 0x0000;
inline constexpr std::uint16_t kQuickStop = 0x0002;
inline constexpr std::uint16_t kShutdown = 0x0006;
inline constexpr std::uint16_t kSwitchOn = 0x0007;
inline constexpr std::uint16_t kEnableOperation = 0x000F;
inline constexpr std::uint16_t kFaultResetBit = 0x0080;  ///< acts on its rising edge only
}  // namespace command

/// What the master wants a drive to do.
enum class Goal {
  Disabled,   ///< power off: Switch on disabled
  Enabled,    ///< Operation enabled (torque on, following the set-points)
  QuickStop,  ///< stop on the drive's quick-stop ramp (from Operation enabled), otherwise power off
};

/// Per-slave controlword sequencer. Each bus cycle: `next(statusword)` returns the controlword to
/// send. With goal Enabled a drive goes Switch on disabled -> (Shutdown) Ready to switch on ->
/// (Switch on) Switched on -> (Enable operation) Operation enabled. A drive in Fault stays there
/// (controlword 0) until `requestFaultReset()`; then bit 7 is sent low for a cycle and high the
/// next (the drive acts on the rising edge, whatever it saw before), repeated until the drive
/// leaves Fault. noexcept, no allocation.
class DriveSequencer {
 public:
  void setGoal(Goal goal) noexcept { goal_ = goal; }
  Goal goal() const noexcept { return goal_; }
  /// Arms a fault reset; it is dropped once the drive is out of Fault.
  void requestFaultReset() noexcept {
    reset_requested_ = true;
    reset_low_sent_ = false;
  }
  bool faultResetPending() const noexcept { return reset_requested_; }

  /// The controlword for this cycle given the drive's last statusword.
  std::uint16_t next(std::uint16_t statusword) noexcept;
  DeviceState state() const noexcept { return state_; }
  /// True when the goal is reached (Enabled: Operation enabled; Disabled: Switch on disabled;
  /// QuickStop: out of Operation enabled and Quick stop active).
  bool atGoal() const noexcept;

 private:
  Goal goal_ = Goal::Disabled;
  DeviceState state_ = DeviceState::Unknown;
  std::uint16_t last_ = 0;
  bool reset_requested_ = false, reset_low_sent_ = false;
};

}  // namespace cobra::fieldbus::cia402
