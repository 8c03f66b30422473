// SocketCanBus: opening a missing or malformed interface refuses with a message naming it (the
// build machine has no CAN interface: no vcan module), and the conversion to and from Linux's
// can_frame keeps identifiers, lengths and data and drops what CanFrame cannot hold.

#include "cobra/fieldbus/socketcan_bus.hpp"

#include <gtest/gtest.h>

#include "../src/socketcan_frame.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using namespace cobra::fieldbus;
using cobra::test_support::messageOf;

TEST(SocketCanBus, AMissingInterfaceIsRefusedByName) {
  EXPECT_EQ(messageOf([] { SocketCanBus bus("cobra_nocan0"); }),
            "SocketCAN interface 'cobra_nocan0': no network interface has this name (No such device); `ip link` "
            "lists the interfaces, a CAN adapter appears as can0, can1, ...");
  EXPECT_EQ(messageOf([] { SocketCanBus bus("a_name_far_too_long"); }),
            "SocketCAN interface 'a_name_far_too_long': not an interface name (1-15 characters, no '/')");
  EXPECT_EQ(messageOf([] { SocketCanBus bus(""); }),
            "SocketCAN interface '': not an interface name (1-15 characters, no '/')");
  // The loopback interface exists but is no CAN interface (or raw CAN sockets are unavailable).
  EXPECT_CONTAINS(messageOf([] { SocketCanBus bus("lo"); }), "SocketCAN interface 'lo': cannot ");
}

TEST(SocketCanFrame, RoundTripsStandardAndExtendedFrames) {
  CanFrame standard{0x30A, false, 8, {1, 2, 3, 4, 5, 6, 7, 8}};
  CanFrame extended{0x1ABCDE12, true, 3, {9, 8, 7}};
  for (const CanFrame& in : {standard, extended}) {
    const can_frame linux_frame = socketcan::toLinux(in);
    CanFrame out;
    ASSERT_TRUE(socketcan::fromLinux(linux_frame, out));
    EXPECT_EQ(out.id, in.id);
    EXPECT_EQ(out.extended, in.extended);
    EXPECT_EQ(out.length, in.length);
    EXPECT_EQ(out.data, in.data);
  }
  EXPECT_EQ(socketcan::toLinux(extended).can_id, 0x1ABCDE12U | CAN_EFF_FLAG);
  EXPECT_EQ(socketcan::toLinux(CanFrame{0xFFFF, false, 9, {}}).can_id, 0x7FFU);  // 11 bits
  EXPECT_EQ(socketcan::toLinux(CanFrame{0x1, false, 9, {}}).can_dlc, 8);         // at most 8 bytes
}

TEST(SocketCanFrame, ErrorAndRemoteRequestFramesAreNotDelivered) {
  can_frame error{};
  error.can_id = CAN_ERR_FLAG | 0x4;
  can_frame remote{};
  remote.can_id = CAN_RTR_FLAG | 0x123;
  CanFrame out;
  EXPECT_FALSE(socketcan::fromLinux(error, out));
  EXPECT_FALSE(socketcan::fromLinux(remote, out));
}

}  // namespace
