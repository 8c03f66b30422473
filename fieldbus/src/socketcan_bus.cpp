#include "cobra/fieldbus/socketcan_bus.hpp"

#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "socketcan_frame.hpp"

namespace cobra::fieldbus {
namespace {

[[noreturn]] void fail(const std::string& interface, const std::string& why) {
  throw std::runtime_error("SocketCAN interface '" + interface + "': " + why);
}

}  // namespace

SocketCanBus::SocketCanBus(const std::string& interface) : interface_(interface) {
  if (interface.empty() || interface.size() >= IFNAMSIZ || interface.find('/') != std::string::npos)
    fail(interface, "not an interface name (1-" + std::to_string(IFNAMSIZ - 1) + " characters, no '/')");
  const unsigned index = if_nametoindex(interface.c_str());
  if (index == 0)
    fail(interface, "no network interface has this name (" + std::string(std::strerror(errno)) +
                        "); `ip link` lists the interfaces, a CAN adapter appears as can0, can1, ...");
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0)
    fail(interface, "cannot open a raw CAN socket: " + std::string(std::strerror(errno)) +
                        " (is the kernel module can_raw loaded?)");
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    fail(interface, "cannot bind a raw CAN socket to it: " + std::string(std::strerror(error)) +
                        " (is it a CAN interface, and up?)");
  }
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) ::close(fd_);
}

bool SocketCanBus::send(const CanFrame& frame) noexcept {
  const can_frame out = socketcan::toLinux(frame);
  return ::write(fd_, &out, sizeof out) == static_cast<ssize_t>(sizeof out);  // EAGAIN/ENOBUFS: queue full
}

bool SocketCanBus::receive(CanFrame& frame) noexcept {
  can_frame in{};
  // Bounded: skipped frames (error, remote request) do not make this loop long.
  for (int skipped = 0; skipped < 64; ++skipped) {
    if (::read(fd_, &in, sizeof in) != static_cast<ssize_t>(sizeof in)) return false;  // EAGAIN: nothing waiting
    if (socketcan::fromLinux(in, frame)) return true;
  }
  return false;
}

}  // namespace cobra::fieldbus
