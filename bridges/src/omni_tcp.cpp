#include "cobra/bridges/omni_tcp.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/bridges/isur_udp_server.hpp"

namespace cobra::bridges {

namespace {

constexpr int kSendTimeoutMs = 50;  // a peer that does not take a frame within this is treated as dropped

std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

const OmniClientOptions& checked(const OmniClientOptions& o) {
  if (o.port == 0) throw std::runtime_error("Omni client: port is 0: give the Omni application's TCP port");
  if (!(o.reconnect_period > 0.0 && o.reconnect_period <= 10.0))
    throw std::runtime_error("Omni client: reconnect_period is " + std::to_string(o.reconnect_period) +
                             " s: give (0, 10]");
  if (!(o.max_delay >= 0.0 && std::isfinite(o.max_delay)))
    throw std::runtime_error("Omni client: max_delay is " + std::to_string(o.max_delay) + " s: give >= 0");
  return o;
}

// Sleeps up to `ms` in 5 ms slices while `running` holds.
void napWhile(const std::atomic<bool>& running, int ms) {
  for (int t = 0; t < ms && running.load(std::memory_order_relaxed); t += 5)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

}  // namespace

// ---- OmniClient ----------------------------------------------------------------------------

OmniClient::OmniClient(OmniClientOptions options)
    : options_(checked(options)), peer_(resolve(options_.host, options_.port)), lateness_(toNs(options_.max_delay)) {}

OmniClient::~OmniClient() { stop(); }

void OmniClient::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void OmniClient::stop() {
  running_.store(false);
  if (thread_.joinable()) thread_.join();
}

bool OmniClient::serve(int fd) noexcept {
  waitReadable(fd, 1);
  std::size_t received = 0;
  const IoResult r = receiveSome(fd, framer_.space(), received);
  if (r == IoResult::Closed) return false;
  framer_.commit(received);
  std::span<const std::uint8_t> frame;
  wire::DecodeStatus why = wire::DecodeStatus::Ok;
  for (;;) {
    const StreamFramer::Next next = framer_.next(frame, why);
    if (next == StreamFramer::Next::NeedMore) break;
    if (next == StreamFramer::Next::Broken) {
      counters_.count(why);
      return false;
    }
    omni::State st;
    wire::FrameHeader header;
    wire::DecodeStatus status = omni::decode(frame, st, header);
    if (status == wire::DecodeStatus::Ok)
      status = lateness_.accept(header.sequence, header.timestamp_ns, steadyNanoseconds());
    counters_.count(status);
    if (status == wire::DecodeStatus::Ok) state.write(st);
  }
  const std::uint64_t version = command.version();
  if (version != sent_version_) {
    omni::WrenchCommand c;
    if (command.read(c) != 0) {
      std::array<std::uint8_t, omni::kMaxFrameSize> out;
      const std::size_t size = omni::encode(c, {++sequence_, static_cast<std::uint64_t>(steadyNanoseconds())}, out);
      if (sendAll(fd, std::span<const std::uint8_t>(out.data(), size), kSendTimeoutMs) != IoResult::Done) return false;
      sent_version_ = version;
    }
  }
  return true;
}

void OmniClient::run() noexcept {
  const int reconnect_ms = static_cast<int>(std::lround(options_.reconnect_period * 1e3));
  while (running_.load(std::memory_order_relaxed)) {
    int error = 0;
    FileDescriptor fd = connectTcp(peer_, 100, error);
    if (!fd.valid()) {
      napWhile(running_, reconnect_ms);
      continue;
    }
    framer_.clear();
    lateness_.reset();  // a new connection may be a restarted application: sequence numbers restart
    sent_version_ = 0;  // the new peer has not seen the current command yet
    connections_.fetch_add(1);
    connected_.store(true);
    while (running_.load(std::memory_order_relaxed) && serve(fd.get())) {
    }
    connected_.store(false);
    if (running_.load(std::memory_order_relaxed)) {
      drops_.fetch_add(1);
      napWhile(running_, reconnect_ms);
    }
  }
}

}  // namespace cobra::bridges
