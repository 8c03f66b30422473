// Cia402Drive: every transition of the CiA 402 state machine checked against the standard's
// statusword table (decoded here independently of the drive), fault reset on the rising edge of
// bit 7, modes of operation, injected and detected faults, no allocation, parameter errors; the
// external-plant cycle against step().

#include "cobra/sim/cia402_drive.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::Cia402Drive;
using cobra::sim::Cia402DriveModel;
using cobra::sim::Cia402Mode;
using cobra::sim::Cia402State;
namespace cw = cobra::sim::controlword;

/// The statusword table of IEC 61800-7-201 / CiA 402 (bits 0-3, 5, 6), "x" bits masked out.
Cia402State decode(std::uint16_t sw) {
  if ((sw & 0x4F) == 0x00) return Cia402State::NotReadyToSwitchOn;
  if ((sw & 0x4F) == 0x40) return Cia402State::SwitchOnDisabled;
  if ((sw & 0x6F) == 0x21) return Cia402State::ReadyToSwitchOn;
  if ((sw & 0x6F) == 0x23) return Cia402State::SwitchedOn;
  if ((sw & 0x6F) == 0x27) return Cia402State::OperationEnabled;
  if ((sw & 0x6F) == 0x07) return Cia402State::QuickStopActive;
  if ((sw & 0x4F) == 0x0F) return Cia402State::FaultReactionActive;
  if ((sw & 0x4F) == 0x08) return Cia402State::Fault;
  ADD_FAILURE() << "statusword 0x" << std::hex << sw << " matches no state of the table";
  return Cia402State::NotReadyToSwitchOn;
}

constexpr double kCycle = 1e-3;  // s, the bus cycle

/// Writes `word`, steps one cycle, and checks the decoded statusword and the reported state.
void expectAfter(Cia402Drive& drive, std::uint16_t word, Cia402State expected, const char* transition) {
  drive.setControlword(word);
  const std::uint16_t sw = drive.step(kCycle);
  EXPECT_EQ(decode(sw), expected) << transition << ": statusword 0x" << std::hex << sw;
  EXPECT_EQ(drive.state(), expected) << transition << ": " << cobra::sim::toString(drive.state());
}

void enable(Cia402Drive& drive) {
  expectAfter(drive, cw::kShutdown, Cia402State::ReadyToSwitchOn, "2");
  expectAfter(drive, cw::kSwitchOnCommand, Cia402State::SwitchedOn, "3");
  expectAfter(drive, cw::kEnableOperationCommand, Cia402State::OperationEnabled, "4");
}

TEST(Cia402Drive, StartsNotReadyThenSwitchOnDisabled) {
  Cia402Drive drive(Cia402DriveModel{});
  EXPECT_EQ(decode(drive.statusword()), Cia402State::NotReadyToSwitchOn);
  expectAfter(drive, cw::kDisableVoltage, Cia402State::SwitchOnDisabled, "1");
  EXPECT_EQ(drive.statusword(), 0x0250);  // switch on disabled + voltage enabled + remote
}

TEST(Cia402Drive, EveryControlwordTransitionFollowsTheTable) {
  Cia402Drive drive(Cia402DriveModel{});
  expectAfter(drive, 0, Cia402State::SwitchOnDisabled, "1");
  expectAfter(drive, cw::kSwitchOnCommand, Cia402State::SwitchOnDisabled, "no transition from switch on disabled");
  enable(drive);
  EXPECT_EQ(drive.statusword() & 0x6F, 0x27);
  expectAfter(drive, cw::kSwitchOnCommand, Cia402State::SwitchedOn, "5");
  expectAfter(drive, cw::kShutdown, Cia402State::ReadyToSwitchOn, "6");
  expectAfter(drive, cw::kDisableVoltage, Cia402State::SwitchOnDisabled, "7 (disable voltage)");
  expectAfter(drive, cw::kShutdown, Cia402State::ReadyToSwitchOn, "2");
  expectAfter(drive, cw::kQuickStopCommand, Cia402State::SwitchOnDisabled, "7 (quick stop)");
  enable(drive);
  expectAfter(drive, cw::kShutdown, Cia402State::ReadyToSwitchOn, "8");
  expectAfter(drive, cw::kEnableOperationCommand, Cia402State::SwitchedOn, "3 (switch on + enable operation)");
  expectAfter(drive, cw::kEnableOperationCommand, Cia402State::OperationEnabled, "4 (second cycle)");
  expectAfter(drive, cw::kDisableVoltage, Cia402State::SwitchOnDisabled, "9");
  expectAfter(drive, cw::kShutdown, Cia402State::ReadyToSwitchOn, "2");
  expectAfter(drive, cw::kSwitchOnCommand, Cia402State::SwitchedOn, "3");
  expectAfter(drive, cw::kDisableVoltage, Cia402State::SwitchOnDisabled, "10 (disable voltage)");
  expectAfter(drive, cw::kShutdown, Cia402State::ReadyToSwitchOn, "2");
  expectAfter(drive, cw::kSwitchOnCommand, Cia402State::SwitchedOn, "3");
  expectAfter(drive, cw::kQuickStopCommand, Cia402State::SwitchOnDisabled, "10 (quick stop)");
  enable(drive);
  expectAfter(drive, cw::kQuickStopCommand, Cia402State::QuickStopActive, "11");
  EXPECT_EQ(drive.statusword() & 0x6F, 0x07);
  expectAfter(drive, cw::kDisableVoltage, Cia402State::SwitchOnDisabled, "12 (disable voltage)");
}

TEST(Cia402Drive, QuickStopOption2StopsOnTheRampThenDisables) {
  Cia402Drive drive(Cia402DriveModel{});
  drive.setModeOfOperation(Cia402Mode::CyclicSynchronousVelocity);
  drive.step(kCycle);
  enable(drive);
  drive.setTargetVelocity(2.0);
  for (int i = 0; i < 500; ++i) drive.step(kCycle);
  ASSERT_NEAR(drive.velocity(), 2.0, 0.02);
  expectAfter(drive, cw::kQuickStopCommand, Cia402State::QuickStopActive, "11");
  int cycles = 1;
  while (drive.state() == Cia402State::QuickStopActive && cycles < 1000) {
    drive.step(kCycle);
    ++cycles;
  }
  EXPECT_EQ(decode(drive.statusword()), Cia402State::SwitchOnDisabled);  // 12, automatic
  EXPECT_NEAR(cycles * kCycle, 2.0 / 40.0, 0.01);  // v / quick_stop_deceleration, plus the loop's lag
}

TEST(Cia402Drive, QuickStopOption6AllowsTransition16) {
  Cia402DriveModel model;
  model.quick_stop_option = 6;
  Cia402Drive drive(model);
  drive.step(kCycle);
  enable(drive);
  expectAfter(drive, cw::kQuickStopCommand, Cia402State::QuickStopActive, "11");
  for (int i = 0; i < 10; ++i) expectAfter(drive, cw::kQuickStopCommand, Cia402State::QuickStopActive, "option 6 stays");
  expectAfter(drive, cw::kEnableOperationCommand, Cia402State::OperationEnabled, "16");
}

TEST(Cia402Drive, InjectedFaultGoesThroughFaultReactionAndResetsOnlyOnARisingEdge) {
  Cia402Drive drive(Cia402DriveModel{});
  drive.step(kCycle);
  enable(drive);
  drive.injectFault(0x5530);
  expectAfter(drive, cw::kEnableOperationCommand | cw::kFaultReset, Cia402State::FaultReactionActive, "13");
  EXPECT_EQ(drive.errorCode(), 0x5530);
  expectAfter(drive, cw::kEnableOperationCommand | cw::kFaultReset, Cia402State::Fault, "14");
  EXPECT_DOUBLE_EQ(drive.torque(), 0.0);
  expectAfter(drive, cw::kFaultReset, Cia402State::Fault, "bit 7 held high from before: no edge");
  expectAfter(drive, 0, Cia402State::Fault, "bit 7 low");
  expectAfter(drive, cw::kFaultReset, Cia402State::SwitchOnDisabled, "15");
  EXPECT_EQ(drive.errorCode(), 0);
}

TEST(Cia402Drive, CyclicSynchronousPositionTracksAndReachesTheTarget) {
  Cia402Drive drive(Cia402DriveModel{}, 0.1);
  drive.step(kCycle);
  enable(drive);
  for (int i = 0; i < 1000; ++i) {
    drive.setTargetPosition(0.1 + 0.5 * std::sin(i * kCycle));
    drive.step(kCycle);
    EXPECT_LT(std::abs(drive.position() - (0.1 + 0.5 * std::sin(i * kCycle))), 0.02);
  }
  const double held = 0.1 + 0.5 * std::sin(999 * kCycle);
  for (int i = 0; i < 500; ++i) drive.step(kCycle);
  EXPECT_TRUE(drive.statusword() & cobra::sim::statusword::kTargetReached);
  EXPECT_NEAR(drive.position(), held, 1e-3);
}

TEST(Cia402Drive, ProfilePositionTakesTheSetPointOnBit4AndRespectsTheProfileVelocity) {
  Cia402Drive drive(Cia402DriveModel{});
  drive.setModeOfOperation(Cia402Mode::ProfilePosition);
  drive.step(kCycle);
  enable(drive);
  drive.setTargetPosition(1.0);
  drive.step(kCycle);
  EXPECT_NEAR(drive.position(), 0.0, 1e-6);  // no new set-point yet
  drive.setControlword(cw::kEnableOperationCommand | cw::kNewSetPoint);
  double peak_velocity = 0.0;
  for (int i = 0; i < 1500; ++i) {
    drive.step(kCycle);
    peak_velocity = std::max(peak_velocity, drive.velocity());
  }
  EXPECT_TRUE(drive.statusword() & cobra::sim::statusword::kSetPointAcknowledge);
  EXPECT_TRUE(drive.statusword() & cobra::sim::statusword::kTargetReached);
  EXPECT_NEAR(drive.position(), 1.0, 1e-3);
  EXPECT_LT(peak_velocity, 2.0 * 1.05);
  EXPECT_GT(peak_velocity, 2.0 * 0.9);
}

TEST(Cia402Drive, CyclicSynchronousTorqueAcceleratesTheInertia) {
  Cia402DriveModel model;
  model.viscous_friction = 0.0;
  Cia402Drive drive(model);
  drive.setModeOfOperation(Cia402Mode::CyclicSynchronousTorque);
  drive.step(kCycle);
  enable(drive);
  drive.setTargetTorque(0.5);
  for (int i = 0; i < 100; ++i) drive.step(kCycle);
  EXPECT_NEAR(drive.velocity(), 0.5 / 0.01 * 0.1, 1e-9);  // τ/J·t
  EXPECT_NEAR(drive.current(), 0.5 / 0.5, 1e-12);
}

TEST(Cia402Drive, OverCurrentAndFollowingErrorRaiseTheirFaults) {
  Cia402Drive torque_drive(Cia402DriveModel{});
  torque_drive.setModeOfOperation(Cia402Mode::CyclicSynchronousTorque);
  torque_drive.step(kCycle);
  enable(torque_drive);
  torque_drive.setTargetTorque(20.0);  // 40 A demanded > 28.2 A peak
  int cycles = 0;
  while (torque_drive.state() == Cia402State::OperationEnabled && cycles < 1000) {
    torque_drive.step(kCycle);
    ++cycles;
    if (torque_drive.state() == Cia402State::OperationEnabled) {
      EXPECT_TRUE(torque_drive.statusword() & cobra::sim::statusword::kInternalLimit);
    }
  }
  EXPECT_EQ(torque_drive.errorCode(), cobra::sim::error_code::kOverCurrent);
  EXPECT_EQ(cycles, 50);  // over_current_time 50 ms

  Cia402Drive blocked(Cia402DriveModel{});
  blocked.step(kCycle);
  enable(blocked);
  blocked.setLoadTorque(-100.0);  // far beyond what the motor can hold
  for (int i = 0; i < 200 && blocked.state() == Cia402State::OperationEnabled; ++i) blocked.step(kCycle);
  EXPECT_EQ(blocked.errorCode(), cobra::sim::error_code::kFollowingError);
}

TEST(Cia402Drive, StepAllocatesNothing) {
  Cia402Drive drive(Cia402DriveModel{});
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              drive.step(kCycle);
              enable(drive);
              for (int i = 0; i < 1000; ++i) {
                drive.setTargetPosition(0.001 * i);
                drive.step(kCycle);
              }
            }),
            0);
}

TEST(Cia402Drive, BadParametersAreNamed) {
  Cia402DriveModel m;
  m.peak_current = 10.0;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { Cia402Drive d(m); }),
                  "CiA 402 drive: peak_current = 10.000000, expected >= 14.100000 A (continuous_current)");
  m = Cia402DriveModel{};
  m.quick_stop_option = 3;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { Cia402Drive d(m); }), "quick_stop_option = 3, expected 2");
}

// The external-plant cycle (beginCycle, controlTorque per integration step, endCycle) with the
// plant integrated outside the drive, as MuJoCo does, gives the same drive as step() with its own
// motor: the same integrator written here (semi-implicit Euler of J·dω/dt = τ − b·ω) must reproduce
// step()'s trajectory exactly, through enable, a CSP move with a following-error fault and reset.
TEST(Cia402Drive, TheExternalPlantCycleIsStepWithThePlantOutside) {
  const Cia402DriveModel model;
  Cia402Drive own(model, 0.1), outside(model, 0.1);
  double q = 0.1, v = 0.0;  // the outside plant, rad and rad/s
  bool faulted = false;
  const double h = model.internal_period;
  const int substeps = static_cast<int>(std::ceil(kCycle / h - 1e-9));
  for (int k = 0; k < 600; ++k) {
    const std::uint16_t word = k < 2 ? cw::kShutdown : k < 4 ? cw::kSwitchOnCommand
                               : k == 400 ? static_cast<std::uint16_t>(cw::kFaultReset) : cw::kEnableOperationCommand;
    const double target = k < 200 ? 0.1 + 0.5 * k * kCycle : 0.5;  // a jump at 200 ms: following error
    for (Cia402Drive* d : {&own, &outside}) {
      d->setControlword(word);
      d->setTargetPosition(target);
    }
    own.step(kCycle);
    outside.beginCycle();
    for (int i = 0; i < substeps; ++i) {
      const double torque = outside.controlTorque(kCycle / substeps, q, v);
      v = (v + h * torque / model.inertia) / (1.0 + h * model.viscous_friction / model.inertia);
      q += v * h;
    }
    outside.endCycle(kCycle, q, v);
    ASSERT_EQ(outside.statusword(), own.statusword()) << "cycle " << k;
    ASSERT_EQ(outside.position(), own.position()) << "cycle " << k;
    ASSERT_EQ(outside.torque(), own.torque()) << "cycle " << k;
    faulted = faulted || own.state() == Cia402State::Fault;
  }
  EXPECT_TRUE(faulted);  // the jump did trip the following error
  EXPECT_EQ(own.state(), Cia402State::SwitchOnDisabled);  // reset at 400 ms
}

}  // namespace
