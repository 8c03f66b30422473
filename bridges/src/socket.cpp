#include "cobra/bridges/socket.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace cobra::bridges {

namespace {

[[noreturn]] void fail(const std::string& what, int error) {
  throw std::runtime_error(what + ": " + std::strerror(error));
}

void setNonBlocking(int fd) noexcept {
  const int flags = ::fcntl(fd, F_GETFL, 0);
  ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
}

Endpoint localOf(int fd) {
  Endpoint e;
  socklen_t len = sizeof(e.address);
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&e.address), &len) != 0) fail("getsockname", errno);
  return e;
}

FileDescriptor boundSocket(int type, const std::string& host, std::uint16_t port) {
  const Endpoint at = resolve(host, port);
  FileDescriptor fd(::socket(AF_INET, type | SOCK_CLOEXEC, 0));
  if (!fd.valid()) fail("socket", errno);
  const int yes = 1;
  ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&at.address), sizeof(at.address)) != 0)
    fail("cannot bind to " + at.text(), errno);
  setNonBlocking(fd.get());
  return fd;
}

}  // namespace

std::string Endpoint::text() const {
  char buffer[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &address.sin_addr, buffer, sizeof(buffer));
  return std::string(buffer) + ":" + std::to_string(port());
}

std::uint16_t Endpoint::port() const noexcept { return ntohs(address.sin_port); }

Endpoint resolve(const std::string& host, std::uint16_t port) {
  Endpoint e;
  e.address.sin_family = AF_INET;
  e.address.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &e.address.sin_addr) == 1) return e;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  addrinfo* found = nullptr;
  if (const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &found); rc != 0 || found == nullptr)
    throw std::runtime_error("cannot resolve host '" + host + "': " + ::gai_strerror(rc));
  e.address.sin_addr = reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr;
  ::freeaddrinfo(found);
  return e;
}

FileDescriptor& FileDescriptor::operator=(FileDescriptor&& other) noexcept {
  if (this != &other) {
    reset();
    fd_ = other.release();
  }
  return *this;
}

int FileDescriptor::release() noexcept {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

void FileDescriptor::reset() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool waitReadable(int fd, int timeout_ms) noexcept {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, timeout_ms) > 0;
}

UdpSocket::UdpSocket(const std::string& host, std::uint16_t port) : fd_(boundSocket(SOCK_DGRAM, host, port)) {}

Endpoint UdpSocket::local() const { return localOf(fd_.get()); }

bool UdpSocket::sendTo(const Endpoint& to, std::span<const std::uint8_t> bytes) noexcept {
  const ssize_t n = ::sendto(fd_.get(), bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL,
                             reinterpret_cast<const sockaddr*>(&to.address), sizeof(to.address));
  return n == static_cast<ssize_t>(bytes.size());
}

std::size_t UdpSocket::receive(std::span<std::uint8_t> buffer, bool& truncated, Endpoint* from) noexcept {
  sockaddr_in sender{};
  socklen_t len = sizeof(sender);
  // MSG_TRUNC: the return value is the datagram's real size, so an oversized one is detected.
  const ssize_t n = ::recvfrom(fd_.get(), buffer.data(), buffer.size(), MSG_DONTWAIT | MSG_TRUNC,
                               reinterpret_cast<sockaddr*>(&sender), &len);
  if (n < 0) return 0;
  if (from != nullptr) from->address = sender;
  truncated = static_cast<std::size_t>(n) > buffer.size();
  // An empty datagram is reported as a one-byte truncated one: it is a (malformed) arrival.
  if (n == 0) {
    truncated = true;
    return 1;
  }
  return truncated ? buffer.size() : static_cast<std::size_t>(n);
}

TcpListener::TcpListener(const std::string& host, std::uint16_t port) : fd_(boundSocket(SOCK_STREAM, host, port)) {
  if (::listen(fd_.get(), 4) != 0) fail("cannot listen on " + host + ":" + std::to_string(port), errno);
}

Endpoint TcpListener::local() const { return localOf(fd_.get()); }

FileDescriptor TcpListener::accept(int timeout_ms) noexcept {
  if (!waitReadable(fd_.get(), timeout_ms)) return FileDescriptor();
  FileDescriptor client(::accept4(fd_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
  if (client.valid()) {
    const int yes = 1;
    ::setsockopt(client.get(), IPPROTO_TCP, TCP_NODELAY, &yes, sizeof(yes));
  }
  return client;
}

FileDescriptor connectTcp(const Endpoint& to, int timeout_ms, int& error) noexcept {
  error = 0;
  FileDescriptor fd(::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!fd.valid()) {
    error = errno;
    return fd;
  }
  const int yes = 1;
  ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &yes, sizeof(yes));
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&to.address), sizeof(to.address)) == 0) return fd;
  if (errno != EINPROGRESS) {
    error = errno;
    return FileDescriptor();
  }
  pollfd p{fd.get(), POLLOUT, 0};
  if (::poll(&p, 1, timeout_ms) <= 0) {
    error = ETIMEDOUT;
    return FileDescriptor();
  }
  int so_error = 0;
  socklen_t len = sizeof(so_error);
  ::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &so_error, &len);
  if (so_error != 0) {
    error = so_error;
    return FileDescriptor();
  }
  return fd;
}

IoResult sendAll(int fd, std::span<const std::uint8_t> bytes, int timeout_ms) noexcept {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return IoResult::Closed;
    const auto now = std::chrono::steady_clock::now();
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    if (left.count() <= 0) return IoResult::Closed;
    pollfd p{fd, POLLOUT, 0};
    ::poll(&p, 1, static_cast<int>(left.count()));
  }
  return IoResult::Done;
}

IoResult receiveSome(int fd, std::span<std::uint8_t> buffer, std::size_t& received) noexcept {
  received = 0;
  const ssize_t n = ::recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
  if (n > 0) {
    received = static_cast<std::size_t>(n);
    return IoResult::Done;
  }
  if (n == 0) return IoResult::Closed;
  return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? IoResult::WouldBlock : IoResult::Closed;
}

}  // namespace cobra::bridges
