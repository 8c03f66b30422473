#include "cobra/bridges/isur_udp_server.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace cobra::bridges {

namespace {

std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

const IsurUdpServerOptions& checked(const IsurUdpServerOptions& o) {
  const std::string who = "I-SUR server: ";
  if (o.controller_port == 0) throw std::runtime_error(who + "controller_port is 0: give the controller's UDP port");
  if (o.joints < 1 || o.joints > isur::kMaxJoints)
    throw std::runtime_error(who + "joints is " + std::to_string(o.joints) + ": give 1..16");
  if (o.tools < 1 || o.tools > isur::kMaxTools)
    throw std::runtime_error(who + "tools is " + std::to_string(o.tools) + ": give 1.." +
                             std::to_string(isur::kMaxTools));
  if (!(o.command_period > 0.0 && o.command_period <= 1.0))
    throw std::runtime_error(who + "command_period is " + std::to_string(o.command_period) + " s: give (0, 1]");
  if (!(o.max_delay >= 0.0 && std::isfinite(o.max_delay)))
    throw std::runtime_error(who + "max_delay is " + std::to_string(o.max_delay) + " s: give >= 0");
  if (!(o.resync_after > 0.0 && std::isfinite(o.resync_after)))
    throw std::runtime_error(who + "resync_after is " + std::to_string(o.resync_after) + " s: give > 0");
  return o;
}

}  // namespace

std::int64_t steadyNanoseconds() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

IsurUdpServer::IsurUdpServer(IsurUdpServerOptions options)
    : options_(checked(options)),
      block_(options_.shm_name),
      socket_(options_.bind_host, options_.bind_port),
      controller_(resolve(options_.controller_host, options_.controller_port)),
      lateness_(toNs(options_.max_delay)) {}

IsurUdpServer::~IsurUdpServer() { stop(); }

void IsurUdpServer::start() {
  if (running_.exchange(true)) return;
  last_valid_ns_ = steadyNanoseconds();
  thread_ = std::thread([this] { run(); });
}

void IsurUdpServer::stop() {
  running_.store(false);
  if (thread_.joinable()) thread_.join();
}

void IsurUdpServer::receiveAll(std::int64_t now_ns) noexcept {
  std::array<std::uint8_t, isur::kMaxFrameSize + 1> buffer;
  for (;;) {
    bool truncated = false;
    const std::size_t n = socket_.receive(buffer, truncated);
    if (n == 0) return;
    if (truncated) {  // larger than any valid frame, or empty
      block_->counters.count(n == 1 ? wire::DecodeStatus::Truncated : wire::DecodeStatus::BadLength);
      continue;
    }
    isur::State state;
    wire::FrameHeader header;
    wire::DecodeStatus status = isur::decode(std::span<const std::uint8_t>(buffer.data(), n), state, header);
    if (status == wire::DecodeStatus::Ok && state.joint_count != options_.joints)
      status = wire::DecodeStatus::WrongJointCount;
    if (status == wire::DecodeStatus::Ok && state.tool_count != options_.tools)
      status = wire::DecodeStatus::WrongToolCount;
    if (status == wire::DecodeStatus::Ok) status = lateness_.accept(header.sequence, header.timestamp_ns, now_ns);
    block_->counters.count(status);
    if (status != wire::DecodeStatus::Ok) continue;
    block_->state.write(state);
    acknowledged_request_ = state.actuation_request;
    last_valid_ns_ = now_ns;
  }
}

void IsurUdpServer::send(const isur::Command& command) noexcept {
  const std::size_t size = isur::encode(command, {++sequence_, static_cast<std::uint64_t>(steadyNanoseconds())}, out_);
  if (size > 0 && socket_.sendTo(controller_, std::span<const std::uint8_t>(out_.data(), size)))
    block_->commands_sent.fetch_add(1, std::memory_order_relaxed);
}

void IsurUdpServer::run() noexcept {
  const std::int64_t period_ns = toNs(options_.command_period);
  const std::int64_t resync_ns = toNs(options_.resync_after);
  std::uint64_t sent_version = 0, sent_actuation_version = 0;
  std::int64_t next_send_ns = steadyNanoseconds(), next_actuation_ns = next_send_ns;
  while (running_.load(std::memory_order_relaxed)) {
    waitReadable(socket_.fd(), 1);
    const std::int64_t now = steadyNanoseconds();
    receiveAll(now);
    if (now - last_valid_ns_ > resync_ns) {
      lateness_.reset();
      last_valid_ns_ = now;
    }
    // A new command goes out at once; the latest one is repeated every period.
    const std::uint64_t version = block_->command.version();
    isur::Command command;
    if (version != 0 && (version != sent_version || now >= next_send_ns) && block_->command.read(command) != 0) {
      send(command);
      sent_version = version;
      next_send_ns = now + period_ns;
    }
    // A new actuation request goes out at once, and again every period until a state acknowledges it.
    const std::uint64_t actuation_version = block_->actuation.version();
    isur::Command actuation;
    actuation.type = isur::MessageType::ToolActuation;
    if (actuation_version != 0 && (actuation_version != sent_actuation_version || now >= next_actuation_ns) &&
        block_->actuation.read(actuation.actuation) != 0 && actuation.actuation.request != acknowledged_request_) {
      send(actuation);
      sent_actuation_version = actuation_version;
      next_actuation_ns = now + period_ns;
    }
  }
}

}  // namespace cobra::bridges
