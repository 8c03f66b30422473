// The master side of CiA 402: the statusword decoder against hand-built words of the standard's
// table and cross-checked against cobra::sim::Cia402Drive over every transition the drive can
// make; the controlword sequencer enabling a drive, quick-stopping it and resetting a fault on
// the rising edge of bit 7.

#include "cobra/fieldbus/cia402.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>

#include "cobra/sim/cia402_drive.hpp"

namespace {

using cobra::fieldbus::cia402::decodeStatusword;
using cobra::fieldbus::cia402::DeviceState;
using cobra::fieldbus::cia402::DriveSequencer;
using cobra::fieldbus::cia402::Goal;
namespace command = cobra::fieldbus::cia402::command;
using cobra::sim::Cia402State;

DeviceState expected(Cia402State s) {
  switch (s) {
    case Cia402State::NotReadyToSwitchOn:
      return DeviceState::NotReadyToSwitchOn;
    case Cia402State::SwitchOnDisabled:
      return DeviceState::SwitchOnDisabled;
    case Cia402State::ReadyToSwitchOn:
      return DeviceState::ReadyToSwitchOn;
    case Cia402State::SwitchedOn:
      return DeviceState::SwitchedOn;
    case Cia402State::OperationEnabled:
      return DeviceState::OperationEnabled;
    case Cia402State::QuickStopActive:
      return DeviceState::QuickStopActive;
    case Cia402State::FaultReactionActive:
      return DeviceState::FaultReactionActive;
    case Cia402State::Fault:
      return DeviceState::Fault;
  }
  return DeviceState::Unknown;
}

TEST(Cia402Decoder, ReadsTheStandardsTableAndIgnoresTheOtherBits) {
  EXPECT_EQ(decodeStatusword(0x0000), DeviceState::NotReadyToSwitchOn);
  EXPECT_EQ(decodeStatusword(0x0040), DeviceState::SwitchOnDisabled);
  EXPECT_EQ(decodeStatusword(0x0021), DeviceState::ReadyToSwitchOn);
  EXPECT_EQ(decodeStatusword(0x0023), DeviceState::SwitchedOn);
  EXPECT_EQ(decodeStatusword(0x0027), DeviceState::OperationEnabled);
  EXPECT_EQ(decodeStatusword(0x0007), DeviceState::QuickStopActive);
  EXPECT_EQ(decodeStatusword(0x000F), DeviceState::FaultReactionActive);
  EXPECT_EQ(decodeStatusword(0x0008), DeviceState::Fault);
  // Voltage enabled, remote, target reached, internal limit, following error: state unchanged.
  EXPECT_EQ(decodeStatusword(0x0027 | 0x0010 | 0x0200 | 0x0400 | 0x0800 | 0x2000), DeviceState::OperationEnabled);
  EXPECT_EQ(decodeStatusword(0xFFB0 & ~0x0040), DeviceState::NotReadyToSwitchOn);
  EXPECT_EQ(decodeStatusword(0x0060), DeviceState::SwitchOnDisabled);  // bit 5 is "x" there
  EXPECT_EQ(decodeStatusword(0x0001), DeviceState::Unknown);           // ready without quick-stop bit
  EXPECT_EQ(decodeStatusword(0x0041), DeviceState::Unknown);
  EXPECT_STREQ(cobra::fieldbus::cia402::toString(DeviceState::QuickStopActive), "quick_stop_active");
}

// 20 000 seeded random controlwords and injected faults on two drives (quick-stop options 2 and
// 6): after every cycle the decoded statusword is the drive's state, and every transition of the
// standard is seen at least once.
TEST(Cia402Decoder, AgreesWithTheSimulatedDriveOnEveryTransition) {
  const std::uint16_t words[] = {
      command::kDisableVoltage,  command::kQuickStop,     command::kShutdown, command::kSwitchOn,
      command::kEnableOperation, command::kFaultResetBit, 0x0080 | 0x000F,    0x0004};
  for (int option : {2, 6}) {
    cobra::sim::Cia402DriveModel model;
    model.quick_stop_option = option;
    cobra::sim::Cia402Drive drive(model);
    std::mt19937_64 rng(static_cast<std::uint64_t>(option));
    std::set<std::pair<Cia402State, Cia402State>> seen;
    Cia402State before = drive.state();
    for (int i = 0; i < 20000; ++i) {
      if (rng() % 50 == 0) drive.injectFault(cobra::sim::error_code::kOverCurrent);
      drive.setControlword(words[rng() % std::size(words)]);
      const std::uint16_t sw = drive.step(1e-3);
      ASSERT_EQ(decodeStatusword(sw), expected(drive.state())) << "statusword 0x" << std::hex << sw;
      seen.insert({before, drive.state()});
      before = drive.state();
    }
    using S = Cia402State;
    std::set<std::pair<S, S>> standard = {
        {S::NotReadyToSwitchOn, S::SwitchOnDisabled},   // 1
        {S::SwitchOnDisabled, S::ReadyToSwitchOn},      // 2
        {S::ReadyToSwitchOn, S::SwitchedOn},            // 3
        {S::SwitchedOn, S::OperationEnabled},           // 4
        {S::OperationEnabled, S::SwitchedOn},           // 5
        {S::SwitchedOn, S::ReadyToSwitchOn},            // 6
        {S::ReadyToSwitchOn, S::SwitchOnDisabled},      // 7
        {S::OperationEnabled, S::ReadyToSwitchOn},      // 8
        {S::OperationEnabled, S::SwitchOnDisabled},     // 9
        {S::SwitchedOn, S::SwitchOnDisabled},           // 10
        {S::OperationEnabled, S::QuickStopActive},      // 11
        {S::QuickStopActive, S::SwitchOnDisabled},      // 12
        {S::OperationEnabled, S::FaultReactionActive},  // 13
        {S::FaultReactionActive, S::Fault},             // 14
        {S::Fault, S::SwitchOnDisabled},                // 15
    };
    if (option == 6) standard.insert({S::QuickStopActive, S::OperationEnabled});  // 16
    for (const auto& t : standard) {
      EXPECT_TRUE(seen.count(t)) << "option " << option << ": never saw " << cobra::sim::toString(t.first) << " -> "
                                 << cobra::sim::toString(t.second);
    }
  }
}

TEST(Cia402Sequencer, EnablesADriveWithShutdownSwitchOnEnableOperation) {
  cobra::sim::Cia402Drive drive{cobra::sim::Cia402DriveModel{}};
  DriveSequencer sequencer;
  sequencer.setGoal(Goal::Enabled);
  std::vector<std::uint16_t> sent;
  for (int i = 0; i < 6; ++i) {
    const std::uint16_t word = sequencer.next(drive.statusword());
    sent.push_back(word);
    drive.setControlword(word);
    drive.step(1e-3);
  }
  // Not ready (0), switch on disabled -> shutdown, ready -> switch on, switched on -> enable, then hold.
  EXPECT_EQ(sent, (std::vector<std::uint16_t>{0x00, 0x06, 0x07, 0x0F, 0x0F, 0x0F}));
  EXPECT_EQ(drive.state(), Cia402State::OperationEnabled);
  sequencer.next(drive.statusword());
  EXPECT_TRUE(sequencer.atGoal());
}

TEST(Cia402Sequencer, QuickStopsThenResetsAFaultOnTheRisingEdgeOnly) {
  cobra::sim::Cia402Drive drive{cobra::sim::Cia402DriveModel{}};
  DriveSequencer sequencer;
  sequencer.setGoal(Goal::Enabled);
  const auto cycle = [&] {
    const std::uint16_t word = sequencer.next(drive.statusword());
    drive.setControlword(word);
    drive.step(1e-3);
    return word;
  };
  for (int i = 0; i < 5; ++i) cycle();
  ASSERT_EQ(drive.state(), Cia402State::OperationEnabled);
  sequencer.setGoal(Goal::QuickStop);
  EXPECT_EQ(cycle(), command::kQuickStop);
  for (int i = 0; i < 20 && drive.state() != Cia402State::SwitchOnDisabled; ++i) cycle();
  EXPECT_EQ(drive.state(), Cia402State::SwitchOnDisabled);  // quick-stop option 2: off once stopped
  sequencer.next(drive.statusword());
  EXPECT_TRUE(sequencer.atGoal());

  sequencer.setGoal(Goal::Enabled);
  for (int i = 0; i < 5; ++i) cycle();
  drive.injectFault(cobra::sim::error_code::kFollowingError);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(cycle() & command::kFaultResetBit, 0);  // no reset unless asked
  ASSERT_EQ(drive.state(), Cia402State::Fault);
  sequencer.requestFaultReset();
  EXPECT_TRUE(sequencer.faultResetPending());
  EXPECT_EQ(cycle(), command::kDisableVoltage);  // bit 7 low first ...
  EXPECT_EQ(cycle(), command::kFaultResetBit);   // ... then high: the edge
  EXPECT_EQ(drive.state(), Cia402State::SwitchOnDisabled);
  EXPECT_EQ(cycle(), command::kShutdown);  // back on the way to Operation enabled
  EXPECT_FALSE(sequencer.faultResetPending());
}

TEST(Cia402Sequencer, HoldingBitSevenHighDoesNotResetTwice) {
  // A drive fed 0x80 continuously resets once; a second fault needs a new edge, which the
  // sequencer makes by dropping bit 7 for one cycle.
  cobra::sim::Cia402Drive drive{cobra::sim::Cia402DriveModel{}};
  drive.step(1e-3);
  drive.injectFault(cobra::sim::error_code::kOverCurrent);
  drive.setControlword(0x80);
  drive.step(1e-3);
  drive.step(1e-3);
  ASSERT_EQ(drive.state(), Cia402State::Fault);
  drive.step(1e-3);  // bit 7 was already high in the fault reaction cycle: no edge
  EXPECT_EQ(drive.state(), Cia402State::Fault);
  DriveSequencer sequencer;
  sequencer.requestFaultReset();
  std::uint16_t previous = 0x80;
  int cycles = 0;
  while (drive.state() == Cia402State::Fault && cycles < 4) {
    const std::uint16_t word = sequencer.next(drive.statusword());
    if (word & command::kFaultResetBit) {
      EXPECT_FALSE(previous & command::kFaultResetBit) << "bit 7 raised without an edge";
    }
    previous = word;
    drive.setControlword(word);
    drive.step(1e-3);
    ++cycles;
  }
  EXPECT_EQ(drive.state(), Cia402State::SwitchOnDisabled);
  EXPECT_EQ(cycles, 2);  // one cycle low, then the edge
}

}  // namespace
