#pragma once
/// @file
/// Thin RAII wrappers over POSIX IPv4 sockets for the bridges' service threads. Set-up calls
/// (resolve, bind, listen) throw std::runtime_error with the address and the system's reason;
/// I/O calls never block longer than the timeout they are given and report by return value.

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace cobra::bridges {

/// An IPv4 address and port.
struct Endpoint {
  sockaddr_in address{};
  /// "127.0.0.1:5000".
  std::string text() const;
  std::uint16_t port() const noexcept;
};

/// Resolves `host` (a dotted address or a name) and `port`.
/// @throws std::runtime_error "cannot resolve host 'x': <reason>".
Endpoint resolve(const std::string& host, std::uint16_t port);

/// An owned file descriptor.
class FileDescriptor {
 public:
  FileDescriptor() = default;
  explicit FileDescriptor(int fd) noexcept : fd_(fd) {}
  ~FileDescriptor() { reset(); }
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(other.release()) {}
  FileDescriptor& operator=(FileDescriptor&& other) noexcept;
  int get() const noexcept { return fd_; }
  bool valid() const noexcept { return fd_ >= 0; }
  int release() noexcept;
  void reset() noexcept;

 private:
  int fd_ = -1;
};

/// Waits up to `timeout_ms` for `fd` to become readable; true when it is (or has an error/hang-up
/// to report through the next read).
bool waitReadable(int fd, int timeout_ms) noexcept;

/// A non-blocking UDP socket bound to a local address.
class UdpSocket {
 public:
  /// Binds to `host`:`port` (port 0: an ephemeral port). @throws std::runtime_error.
  UdpSocket(const std::string& host, std::uint16_t port);
  Endpoint local() const;
  /// Sends one datagram; false when the kernel refused it (buffer full, no route, ...).
  bool sendTo(const Endpoint& to, std::span<const std::uint8_t> bytes) noexcept;
  /// Receives one datagram without waiting. Returns its size (0 when none is pending);
  /// `truncated` is set when the datagram was larger than `buffer`; `from` gets the sender.
  std::size_t receive(std::span<std::uint8_t> buffer, bool& truncated, Endpoint* from = nullptr) noexcept;
  int fd() const noexcept { return fd_.get(); }

 private:
  FileDescriptor fd_;
};

/// A listening TCP socket.
class TcpListener {
 public:
  /// @throws std::runtime_error naming the address.
  TcpListener(const std::string& host, std::uint16_t port);
  Endpoint local() const;
  /// Accepts one pending connection within `timeout_ms`; an invalid descriptor when none came.
  FileDescriptor accept(int timeout_ms) noexcept;
  int fd() const noexcept { return fd_.get(); }

 private:
  FileDescriptor fd_;
};

/// Connects to `to` within `timeout_ms`; returns a non-blocking, TCP_NODELAY stream socket, or an
/// invalid descriptor (with `error` = errno) when it failed.
FileDescriptor connectTcp(const Endpoint& to, int timeout_ms, int& error) noexcept;

/// Result of a non-blocking stream operation.
enum class IoResult { Done, WouldBlock, Closed };

/// Writes all of `bytes` to a non-blocking stream, waiting for room up to `timeout_ms` in total.
/// Closed when the peer is gone or the time ran out with bytes left (a stalled peer is treated
/// as dropped, so a sender never waits forever).
IoResult sendAll(int fd, std::span<const std::uint8_t> bytes, int timeout_ms) noexcept;
/// Reads what is available (up to `buffer.size()`) without waiting; `received` gets the count.
IoResult receiveSome(int fd, std::span<std::uint8_t> buffer, std::size_t& received) noexcept;

}  // namespace cobra::bridges
