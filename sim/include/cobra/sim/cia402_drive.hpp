#pragma once
/// @file
/// A servo drive speaking CiA 402 (IEC 61800-7-201 profile; the thesis' Elmo drives of the
/// Puma 260, §6.1.1, commanded over EtherCAT): the controlword/statusword state machine, modes
/// of operation (profile and cyclic synchronous position, velocity, torque), a motor+load behind
/// the drive's control loops, and fault injection. Joint-side SI units: rad, rad/s, N·m, A.

#include <cstdint>

namespace cobra::sim {

/// States of the CiA 402 power drive system (object 0x6041 decoding).
enum class Cia402State {
  NotReadyToSwitchOn,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
};

/// Stable name ("operation_enabled", ...).
const char* toString(Cia402State state) noexcept;

/// Statusword bits (object 0x6041).
namespace statusword {
inline constexpr std::uint16_t kReadyToSwitchOn = 1U << 0;
inline constexpr std::uint16_t kSwitchedOn = 1U << 1;
inline constexpr std::uint16_t kOperationEnabled = 1U << 2;
inline constexpr std::uint16_t kFault = 1U << 3;
inline constexpr std::uint16_t kVoltageEnabled = 1U << 4;
inline constexpr std::uint16_t kQuickStop = 1U << 5;  ///< active low: 0 = quick stop in progress
inline constexpr std::uint16_t kSwitchOnDisabled = 1U << 6;
inline constexpr std::uint16_t kRemote = 1U << 9;
inline constexpr std::uint16_t kTargetReached = 1U << 10;
inline constexpr std::uint16_t kInternalLimit = 1U << 11;
inline constexpr std::uint16_t kSetPointAcknowledge = 1U << 12;  ///< profile position mode
inline constexpr std::uint16_t kFollowingError = 1U << 13;       ///< position modes
}  // namespace statusword

/// Controlword bits (object 0x6040).
namespace controlword {
inline constexpr std::uint16_t kSwitchOn = 1U << 0;
inline constexpr std::uint16_t kEnableVoltage = 1U << 1;
inline constexpr std::uint16_t kQuickStop = 1U << 2;  ///< active low
inline constexpr std::uint16_t kEnableOperation = 1U << 3;
inline constexpr std::uint16_t kNewSetPoint = 1U << 4;  ///< profile position mode
inline constexpr std::uint16_t kFaultReset = 1U << 7;
inline constexpr std::uint16_t kShutdown = 0x06;
inline constexpr std::uint16_t kSwitchOnCommand = 0x07;
inline constexpr std::uint16_t kEnableOperationCommand = 0x0F;
inline constexpr std::uint16_t kDisableVoltage = 0x00;
inline constexpr std::uint16_t kQuickStopCommand = 0x02;
}  // namespace controlword

/// Modes of operation (object 0x6060).
enum class Cia402Mode : std::int8_t {
  ProfilePosition = 1,
  ProfileVelocity = 3,
  ProfileTorque = 4,
  CyclicSynchronousPosition = 8,
  CyclicSynchronousVelocity = 9,
  CyclicSynchronousTorque = 10,
};

/// Error codes (object 0x603F) the model raises (CiA 402 / EN 50325-4 emergency codes).
namespace error_code {
inline constexpr std::uint16_t kNone = 0x0000;
inline constexpr std::uint16_t kOverCurrent = 0x2310;     ///< continuous over-current
inline constexpr std::uint16_t kFollowingError = 0x8611;  ///< position following error
}  // namespace error_code

/// Drive, motor and load. Motor values are ASSUMPTIONS of the order of a Puma 260 joint behind
/// its gear (joint side); the current limits are the thesis' Elmo table (§6.1.1: Ic = 14.1 A,
/// peak 2·Ic).
struct Cia402DriveModel {
  double inertia = 0.01;              ///< kg·m², > 0: motor + load reflected to the joint
  double viscous_friction = 0.02;     ///< N·m·s/rad, >= 0
  double torque_constant = 0.5;       ///< N·m/A, > 0: joint torque per ampere (gear included)
  double continuous_current = 14.1;   ///< A, > 0 (thesis: Elmo Ic)
  double peak_current = 28.2;         ///< A, >= continuous_current (thesis: 2·Ic)
  double over_current_time = 0.05;    ///< s, > 0: time at the peak limit before the over-current fault
  double velocity_bandwidth = 2 * 3.141592653589793 * 40.0;  ///< rad/s, > 0: velocity loop (PI)
  double position_gain = 60.0;        ///< 1/s, > 0: position loop (P, velocity feed-forward)
  double following_error_window = 0.05;   ///< rad, > 0 (object 0x6065)
  double following_error_timeout = 0.01;  ///< s, >= 0 (object 0x6066)
  double position_window = 1e-3;      ///< rad, > 0: target reached (object 0x6067)
  double velocity_window = 1e-2;      ///< rad/s, > 0: target reached in velocity modes (object 0x606D)
  double profile_velocity = 2.0;      ///< rad/s, > 0 (object 0x6081)
  double profile_acceleration = 10.0; ///< rad/s², > 0 (objects 0x6083/0x6084)
  double torque_slope = 50.0;         ///< N·m/s, > 0 (object 0x6087)
  double quick_stop_deceleration = 40.0;  ///< rad/s², > 0 (object 0x6085)
  int quick_stop_option = 2;          ///< 2: stop on the quick-stop ramp then Switch on disabled; 6: stay in Quick stop active (0x605A)
  double internal_period = 1e-4;      ///< s, > 0: the drive's control loop period (sub-steps of step(dt))
};

/// @throws std::invalid_argument naming the parameter and the expected range.
void validate(const Cia402DriveModel& model);

/// One drive on a cyclic bus: the master writes the controlword, the mode and a target, then
/// calls `step(dt)`; the drive evaluates the controlword once (at most one transition per step,
/// as a drive does per bus cycle; "switch on + enable operation" 0x0F goes through Switched on
/// first), runs its loops and the motor for dt and returns the statusword. noexcept, no
/// allocation, deterministic.
///
/// Against an external plant (a physics engine integrates the joint instead of the drive's own
/// motor model) a cycle is split in three: `beginCycle()`, then for each of the plant's integration
/// steps `controlTorque(h, measured position, measured velocity)` gives the motor torque to apply
/// over that step, then `endCycle(dt, position, velocity)` with the state at the end of the cycle.
/// `step(dt)` is exactly that sequence with the drive's own motor model as the plant.
class Cia402Drive {
 public:
  /// Starts in Not ready to switch on; the first step moves it to Switch on disabled.
  /// @throws std::invalid_argument when the model is invalid.
  explicit Cia402Drive(const Cia402DriveModel& model, double initial_position = 0.0);

  void setControlword(std::uint16_t word) noexcept { controlword_ = word; }
  void setModeOfOperation(Cia402Mode mode) noexcept { requested_mode_ = mode; }
  void setTargetPosition(double rad) noexcept { target_position_ = rad; }
  void setTargetVelocity(double rad_per_s) noexcept { target_velocity_ = rad_per_s; }
  void setTargetTorque(double newton_metre) noexcept { target_torque_ = newton_metre; }
  /// An external load torque on the joint (N·m), e.g. gravity or contact.
  void setLoadTorque(double newton_metre) noexcept { load_torque_ = newton_metre; }
  /// Raises a fault with `code` at the next step (fault injection).
  void injectFault(std::uint16_t code) noexcept { injected_fault_ = code; }

  std::uint16_t step(double dt) noexcept;

  /// External plant, part 1: evaluates the controlword (or the injected fault) and the mode, as
  /// the start of `step` does.
  void beginCycle() noexcept;
  /// External plant, part 2: one control-loop period of `h` s (> 0) from the measured joint
  /// position (rad) and velocity (rad/s). @return the joint torque (N·m) to apply over it, limited
  /// by the peak current; 0 when the power stage is off (see `powered`).
  double controlTorque(double h, double position, double velocity) noexcept;
  /// External plant, part 3: the measured state at the end of a cycle of `dt` s; runs the fault
  /// supervision (over-current, following error) and returns the statusword.
  std::uint16_t endCycle(double dt, double position, double velocity) noexcept;
  /// The power stage is on (Operation enabled or Quick stop active): the motor holds torque;
  /// otherwise the joint is free (its brake, if any, is the plant's).
  bool powered() const noexcept {
    return state_ == Cia402State::OperationEnabled || state_ == Cia402State::QuickStopActive;
  }

  std::uint16_t statusword() const noexcept { return statusword_; }
  Cia402State state() const noexcept { return state_; }
  Cia402Mode modeDisplay() const noexcept { return mode_; }  ///< object 0x6061
  std::uint16_t errorCode() const noexcept { return error_code_; }
  double position() const noexcept { return position_; }  ///< rad (0x6064)
  double velocity() const noexcept { return velocity_; }  ///< rad/s (0x606C)
  double torque() const noexcept { return torque_; }      ///< N·m (0x6077)
  double current() const noexcept { return current_; }    ///< A

 private:
  void evaluateControlword() noexcept;
  void enterFault(std::uint16_t code) noexcept;
  double demandedTorque(double h) noexcept;
  void runLoops(double dt) noexcept;
  void superviseFaults(double dt) noexcept;
  void updateStatusword() noexcept;

  Cia402DriveModel model_;
  Cia402State state_ = Cia402State::NotReadyToSwitchOn;
  Cia402Mode requested_mode_ = Cia402Mode::CyclicSynchronousPosition;
  Cia402Mode mode_ = Cia402Mode::CyclicSynchronousPosition;
  std::uint16_t controlword_ = 0;
  std::uint16_t previous_controlword_ = 0;
  std::uint16_t statusword_ = 0;
  std::uint16_t error_code_ = error_code::kNone;
  std::uint16_t injected_fault_ = error_code::kNone;
  double target_position_ = 0, target_velocity_ = 0, target_torque_ = 0, load_torque_ = 0;
  double position_ = 0, velocity_ = 0, torque_ = 0, current_ = 0;
  double setpoint_position_ = 0, setpoint_velocity_ = 0, setpoint_torque_ = 0;  // profile generators
  double pp_target_ = 0;
  double quick_stop_velocity_ = 0;  // rad/s, the quick-stop ramp
  double velocity_integral_ = 0;  // N·m, PI integrator
  double following_error_time_ = 0, over_current_time_ = 0;
  bool following_error_ = false, set_point_acknowledge_ = false, internal_limit_ = false;
};

}  // namespace cobra::sim
