#include "cobra/bridges/sim/omni_server.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/bridges/isur_udp_server.hpp"

namespace cobra::bridges {

namespace {

constexpr int kSendTimeoutMs = 50;  // a client that does not take a frame within this is treated as dropped

std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

const OmniSimServerOptions& checked(const OmniSimServerOptions& o) {
  if (!(o.period > 0.0 && o.period <= 0.1))
    throw std::runtime_error("Omni simulated application: period is " + std::to_string(o.period) + " s: give (0, 0.1]");
  return o;
}

}  // namespace

OmniSimServer::OmniSimServer(OmniSimServerOptions options)
    : options_(checked(options)), listener_(options_.bind_host, options_.bind_port), master_(options_.model) {}

OmniSimServer::~OmniSimServer() { stop(); }

void OmniSimServer::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void OmniSimServer::stop() {
  running_.store(false);
  if (thread_.joinable()) thread_.join();
}

void OmniSimServer::setHandTarget(const KDL::Vector& target) {
  const std::lock_guard lock(mutex_);
  master_.setHandTarget(target);
}

KDL::Vector OmniSimServer::commandedForce() const {
  const std::lock_guard lock(mutex_);
  return commanded_force_;
}

KDL::Vector OmniSimServer::position() const {
  const std::lock_guard lock(mutex_);
  return master_.position();
}

void OmniSimServer::receive(int fd, bool& alive) noexcept {
  std::size_t received = 0;
  if (receiveSome(fd, framer_.space(), received) == IoResult::Closed) {
    alive = false;
    return;
  }
  framer_.commit(received);
  std::span<const std::uint8_t> frame;
  wire::DecodeStatus why = wire::DecodeStatus::Ok;
  for (;;) {
    const StreamFramer::Next next = framer_.next(frame, why);
    if (next == StreamFramer::Next::NeedMore) return;
    if (next == StreamFramer::Next::Broken) {
      counters_.count(why);
      alive = false;
      return;
    }
    omni::WrenchCommand command;
    wire::FrameHeader header;
    wire::DecodeStatus status = omni::decode(frame, command, header);
    if (status == wire::DecodeStatus::Ok)
      status = lateness_.accept(header.sequence, header.timestamp_ns, steadyNanoseconds());
    counters_.count(status);
    if (status != wire::DecodeStatus::Ok) continue;
    const std::lock_guard lock(mutex_);
    commanded_force_ = KDL::Vector(command.wrench[0], command.wrench[1], command.wrench[2]);
    master_.setCommandedForce(commanded_force_);
  }
}

void OmniSimServer::stepAndSend(int fd, double dt, bool& alive) noexcept {
  omni::State st;
  {
    const std::lock_guard lock(mutex_);
    master_.step(dt);
    for (int i = 0; i < 3; ++i) {
      st.position[static_cast<std::size_t>(i)] = master_.measured()(i);
      st.twist[static_cast<std::size_t>(i)] = master_.velocity()(i);
    }
  }
  st.buttons = buttons_.load() & omni::kKnownButtons;
  if (!sending_.load()) return;
  std::array<std::uint8_t, omni::kMaxFrameSize> out;
  const std::size_t size = omni::encode(st, {++sequence_, static_cast<std::uint64_t>(steadyNanoseconds())}, out);
  if (sendAll(fd, std::span<const std::uint8_t>(out.data(), size), kSendTimeoutMs) != IoResult::Done) alive = false;
}

void OmniSimServer::run() noexcept {
  const auto period = std::chrono::nanoseconds(toNs(options_.period));
  while (running_.load(std::memory_order_relaxed)) {
    FileDescriptor client = listener_.accept(5);
    if (!client.valid()) continue;
    accepted_.fetch_add(1);
    framer_.clear();
    lateness_.reset();
    drop_requested_.store(false);
    bool alive = true;
    auto next = std::chrono::steady_clock::now() + period;
    while (alive && running_.load(std::memory_order_relaxed) && !drop_requested_.load()) {
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(next - std::chrono::steady_clock::now());
      const int wait_ms = static_cast<int>(std::max<std::int64_t>(0, left.count()));
      if (waitReadable(client.get(), wait_ms)) receive(client.get(), alive);
      if (!alive || std::chrono::steady_clock::now() < next) continue;
      stepAndSend(client.get(), options_.period, alive);
      next += period;
      if (next < std::chrono::steady_clock::now()) next = std::chrono::steady_clock::now() + period;
    }
  }
}

}  // namespace cobra::bridges
