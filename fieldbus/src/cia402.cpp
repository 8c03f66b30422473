#include "cobra/fieldbus/cia402.hpp"

namespace cobra::fieldbus::cia402 {

const char* toString(DeviceState state) noexcept {
  switch (state) {
    case DeviceState::Unknown:
      return "unknown";
    case DeviceState::NotReadyToSwitchOn:
      return "not_ready_to_switch_on";
    case DeviceState::SwitchOnDisabled:
      return "switch_on_disabled";
    case DeviceState::ReadyToSwitchOn:
      return "ready_to_switch_on";
    case DeviceState::SwitchedOn:
      return "switched_on";
    case DeviceState::OperationEnabled:
      return "operation_enabled";
    case DeviceState::QuickStopActive:
      return "quick_stop_active";
    case DeviceState::FaultReactionActive:
      return "fault_reaction_active";
    case DeviceState::Fault:
      return "fault";
  }
  return "unknown";
}

// The statusword table of IEC 61800-7-201 (- = don't care):
//   ---- ---- -0-- 0000  Not ready to switch on       mask 0x4F
//   ---- ---- -1-- 0000  Switch on disabled           mask 0x4F
//   ---- ---- -01- 0001  Ready to switch on           mask 0x6F
//   ---- ---- -01- 0011  Switched on                  mask 0x6F
//   ---- ---- -01- 0111  Operation enabled            mask 0x6F
//   ---- ---- -00- 0111  Quick stop active            mask 0x6F
//   ---- ---- -0-- 1111  Fault reaction active        mask 0x4F
//   ---- ---- -0-- 1000  Fault                        mask 0x4F
DeviceState decodeStatusword(std::uint16_t sw) noexcept {
  switch (sw & 0x4F) {
    case 0x00:
      return DeviceState::NotReadyToSwitchOn;
    case 0x40:
      return DeviceState::SwitchOnDisabled;
    case 0x0F:
      return DeviceState::FaultReactionActive;
    case 0x08:
      return DeviceState::Fault;
    default:
      break;
  }
  switch (sw & 0x6F) {
    case 0x21:
      return DeviceState::ReadyToSwitchOn;
    case 0x23:
      return DeviceState::SwitchedOn;
    case 0x27:
      return DeviceState::OperationEnabled;
    case 0x07:
      return DeviceState::QuickStopActive;
    default:
      return DeviceState::Unknown;
  }
}

std::uint16_t DriveSequencer::next(std::uint16_t statusword) noexcept {
  state_ = decodeStatusword(statusword);
  std::uint16_t word = command::kDisableVoltage;
  if (state_ == DeviceState::Fault) {
    // Rising edge of bit 7: high only after a cycle of this request in which it was sent low (the
    // drive may have seen bit 7 high before, from another master or an earlier request).
    if (reset_requested_ && reset_low_sent_ && !(last_ & command::kFaultResetBit))
      word = command::kFaultResetBit;
    else
      reset_low_sent_ = true;
  } else {
    if (state_ != DeviceState::FaultReactionActive && state_ != DeviceState::Unknown) reset_requested_ = false;
    switch (goal_) {
      case Goal::Disabled:
        word = command::kDisableVoltage;
        break;
      case Goal::QuickStop:
        word = state_ == DeviceState::OperationEnabled || state_ == DeviceState::QuickStopActive
                   ? command::kQuickStop
                   : command::kDisableVoltage;
        break;
      case Goal::Enabled:
        switch (state_) {
          case DeviceState::SwitchOnDisabled:
            word = command::kShutdown;
            break;  // transition 2
          case DeviceState::ReadyToSwitchOn:
            word = command::kSwitchOn;
            break;                       // 3
          case DeviceState::SwitchedOn:  // 4
          case DeviceState::OperationEnabled:
            word = command::kEnableOperation;
            break;
          // Quick stop active: leave it by Disable voltage (12) and enable again from there.
          default:
            word = command::kDisableVoltage;
            break;
        }
        break;
    }
  }
  last_ = word;
  return word;
}

bool DriveSequencer::atGoal() const noexcept {
  switch (goal_) {
    case Goal::Enabled:
      return state_ == DeviceState::OperationEnabled;
    case Goal::Disabled:
      return state_ == DeviceState::SwitchOnDisabled;
    case Goal::QuickStop:
      return state_ != DeviceState::OperationEnabled && state_ != DeviceState::QuickStopActive &&
             state_ != DeviceState::Unknown;
  }
  return false;
}

}  // namespace cobra::fieldbus::cia402
