#include "cobra/bridges/igtl_link.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/bridges/isur_udp_server.hpp"

namespace cobra::bridges {

namespace {

constexpr int kSendTimeoutMs = 200;  // a peer that does not take a message within this is treated as gone
constexpr int kPollMs = 2;           // wait for bytes at most this long between two sends

std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

const IgtlLinkOptions& checked(const IgtlLinkOptions& o) {
  if (!o.server && o.port == 0) throw std::runtime_error("OpenIGTLink client: port is 0: give the server's TCP port");
  if (!(o.peer_timeout >= 0.0 && std::isfinite(o.peer_timeout)))
    throw std::runtime_error("OpenIGTLink link: peer_timeout is " + std::to_string(o.peer_timeout) + " s: give >= 0");
  if (!(o.reconnect_period > 0.0 && o.reconnect_period <= 10.0))
    throw std::runtime_error("OpenIGTLink client: reconnect_period is " + std::to_string(o.reconnect_period) +
                             " s: give (0, 10]");
  return o;
}

void napWhile(const std::atomic<bool>& running, int ms) {
  for (int t = 0; t < ms && running.load(std::memory_order_relaxed); t += 5)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

}  // namespace

std::string_view dropReasonName(DropReason reason) noexcept {
  switch (reason) {
    case DropReason::None: return "";
    case DropReason::Truncated: return "truncated";
    case DropReason::BadHeader: return "bad_header";
    case DropReason::Oversized: return "oversized";
    case DropReason::BadCrc: return "bad_crc";
    case DropReason::UnknownType: return "unknown_type";
    case DropReason::BadBody: return "bad_body";
    case DropReason::QueueFull: return "queue_full";
    case DropReason::UnknownDevice: return "unknown_device";
    case DropReason::Unmapped: return "unmapped";
    case DropReason::SendFull: return "send_full";
    case DropReason::PlanTooLong: return "plan_too_long";
  }
  return "";
}

DropReason toDropReason(igtl::IgtlError error) noexcept {
  switch (error) {
    case igtl::IgtlError::Ok: return DropReason::None;
    case igtl::IgtlError::Truncated: return DropReason::Truncated;
    case igtl::IgtlError::BadHeader: return DropReason::BadHeader;
    case igtl::IgtlError::Oversized: return DropReason::Oversized;
    case igtl::IgtlError::BadCrc: return DropReason::BadCrc;
    case igtl::IgtlError::UnknownType: return DropReason::UnknownType;
    case igtl::IgtlError::BadBody: return DropReason::BadBody;
  }
  return DropReason::BadBody;
}

IgtlLink::IgtlLink(IgtlLinkOptions options)
    : options_(checked(options)),
      image_bytes_(options_.image_devices.empty()
                       ? 0
                       : igtl::imageMessageSize(types::GrayImage::kMaxWidth, types::GrayImage::kMaxHeight)),
      body_(options_.max_body) {
  if (options_.server) {
    listener_ = std::make_unique<TcpListener>(options_.host, options_.port);
    local_port_ = listener_->local().port();
  } else {
    peer_ = resolve(options_.host, options_.port);
    local_port_ = options_.port;
  }
  const auto blank = std::make_unique<IgtlImage>();  // 64 KiB: not on the stack
  for (std::size_t i = 0; i < options_.image_devices.size(); ++i)
    images_.push_back(std::make_unique<core::TripleBuffer<IgtlImage>>(*blank));
}

IgtlLink::~IgtlLink() { stop(); }

void IgtlLink::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void IgtlLink::stop() {
  running_.store(false);
  if (thread_.joinable()) thread_.join();
}

void IgtlLink::drop(DropReason reason) noexcept {
  by_reason_[static_cast<std::size_t>(reason)].fetch_add(1);
  last_drop_.store(static_cast<std::uint8_t>(reason));
  dropped_.fetch_add(1);
}

void IgtlLink::discardOutgoing() noexcept {
  IgtlOutMessage m;
  while (outgoing.pop(m)) {
  }
  for (auto& image : images_) image->update();
}

namespace {
/// A body size no OpenIGTLink message has (a volume of a few hundred MB is the largest seen): a
/// header saying more comes from a stream whose message boundaries are lost. Closed, not skipped.
constexpr std::uint64_t kMaxSkip = std::uint64_t{1} << 30;
/// Bytes one receive() takes at most before it returns, so that a peer streaming without a pause
/// does not starve what the link sends (the images, the poses, STATUS).
constexpr std::size_t kReceiveBudget = 256 * 1024;
}  // namespace

bool IgtlLink::receive(int fd) noexcept {
  std::size_t taken = 0;
  for (;;) {
    if (taken >= kReceiveBudget) return true;  // the rest on the next pass, after the sends
    std::span<std::uint8_t> into;
    std::array<std::uint8_t, 4096> scratch;
    switch (stage_) {
      case Stage::Header: into = std::span<std::uint8_t>(header_bytes_).subspan(have_); break;
      case Stage::Body: into = std::span<std::uint8_t>(body_).subspan(have_, header_.body_size - have_); break;
      case Stage::Skip: into = std::span<std::uint8_t>(scratch).first(std::min<std::uint64_t>(skip_, scratch.size())); break;
    }
    std::size_t got = 0;
    if (!into.empty()) {
      const IoResult r = receiveSome(fd, into, got);
      if (r == IoResult::Closed) {
        if (stage_ != Stage::Header || have_ > 0) drop(DropReason::Truncated);
        return false;
      }
      if (got == 0) return true;  // nothing more now
      heard_ = true;
      taken += got;
    }
    switch (stage_) {
      case Stage::Header:
        have_ += got;
        if (have_ < igtl::kHeaderSize) continue;
        have_ = 0;
        if (igtl::decodeHeader(header_bytes_, header_) != igtl::IgtlError::Ok) {
          drop(DropReason::BadHeader);  // the message boundaries are lost: close
          return false;
        }
        if (header_.body_size > kMaxSkip) {
          drop(DropReason::BadHeader);  // no message is that long: the boundaries are lost, close
          return false;
        }
        if (header_.body_size > options_.max_body) {
          drop(DropReason::Oversized);
          skip_ = header_.body_size;
          stage_ = Stage::Skip;
        } else {
          stage_ = Stage::Body;
        }
        break;
      case Stage::Body: have_ += got; break;
      case Stage::Skip:
        skip_ -= got;
        if (skip_ == 0) stage_ = Stage::Header;
        continue;
    }
    if (stage_ == Stage::Body && have_ == header_.body_size) {
      const auto body = std::span<const std::uint8_t>(body_).first(static_cast<std::size_t>(header_.body_size));
      const igtl::IgtlError e = igtl::decodeBody(header_, body, message_);
      if (e != igtl::IgtlError::Ok) {
        drop(toDropReason(e));
      } else if (!received.push(message_)) {
        drop(DropReason::QueueFull);
      } else {
        received_.fetch_add(1);
      }
      have_ = 0;
      stage_ = Stage::Header;
    }
  }
}

bool IgtlLink::send(int fd) noexcept {
  IgtlOutMessage m;
  while (outgoing.pop(m)) {
    if (sendAll(fd, std::span<const std::uint8_t>(m.bytes.data(), m.size), kSendTimeoutMs) != IoResult::Done)
      return false;
    sent_.fetch_add(1);
  }
  for (std::size_t i = 0; i < images_.size(); ++i) {
    if (!images_[i]->update()) continue;
    const IgtlImage& taken = images_[i]->front();
    const types::GrayImage& g = taken.image;
    igtl::ImageView view;
    view.width = g.width;
    view.height = g.height;
    view.spacing_x = g.spacing_x;
    view.spacing_y = g.spacing_y;
    view.corner = toIgtlTransform(g.pose);
    view.pixels = g.pixels.data();
    const std::size_t size = g.valid() ? igtl::encodeImage(options_.image_devices[i], view, taken.timestamp, image_bytes_) : 0;
    if (size == 0) continue;  // an empty or invalid image: nothing to send
    if (sendAll(fd, std::span<const std::uint8_t>(image_bytes_.data(), size), kSendTimeoutMs) != IoResult::Done)
      return false;
    sent_.fetch_add(1);
  }
  return true;
}

void IgtlLink::serve(FileDescriptor fd) noexcept {
  stage_ = Stage::Header;
  have_ = 0;
  discardOutgoing();  // what was queued for no one is stale now
  connections_.fetch_add(1);
  connected_.store(true);
  const std::int64_t timeout = toNs(options_.peer_timeout);
  std::int64_t last_heard = steadyNanoseconds();
  while (running_.load(std::memory_order_relaxed)) {
    heard_ = false;
    if (waitReadable(fd.get(), kPollMs) && !receive(fd.get())) break;
    if (heard_) last_heard = steadyNanoseconds();
    if (!send(fd.get())) break;
    if (timeout > 0 && steadyNanoseconds() - last_heard > timeout) break;
  }
  // Stopped rather than lost: what the update queued before the stop still goes out, so that the
  // peer hears the last state, event or refusal of a run that ends (bounded by the send timeout).
  if (!running_.load(std::memory_order_relaxed)) (void)send(fd.get());
  connected_.store(false);
  losses_.fetch_add(1);
}

void IgtlLink::run() noexcept {
  const int reconnect_ms = static_cast<int>(std::lround(options_.reconnect_period * 1e3));
  while (running_.load(std::memory_order_relaxed)) {
    FileDescriptor fd;
    if (listener_) {
      fd = listener_->accept(50);
    } else {
      int error = 0;
      fd = connectTcp(peer_, 100, error);
      if (!fd.valid()) napWhile(running_, reconnect_ms);
    }
    if (!fd.valid()) {
      discardOutgoing();
      continue;
    }
    serve(std::move(fd));
  }
}

}  // namespace cobra::bridges
