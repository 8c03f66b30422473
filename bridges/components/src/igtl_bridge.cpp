#include "cobra/bridges/igtl_bridge.hpp"

#include <cmath>
#include <functional>

#include "cobra/core/error.hpp"

namespace cobra::bridges {

namespace {

std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool isIdentifier(std::string_view s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s.front())) != 0) return false;
  for (const char c : s)
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '_') return false;
  return true;
}

// A device name (or request key) as OpenIGTLink carries it: 1..20 printable characters, none of
// the mapping's separators.
bool isDeviceName(std::string_view s) {
  if (s.empty() || s.size() > igtl::kDeviceSize) return false;
  for (const char c : s)
    if (c < 0x21 || c > 0x7E || c == '=' || c == ',') return false;
  return true;
}

struct Entry {
  std::string_view text;  // the whole entry, for messages
  std::string_view key;
  std::string_view value;
};

// Splits "A=b, C=d" into entries; throws core::Error naming the property and the entry.
std::vector<Entry> splitMapping(std::string_view property, std::string_view text,
                                std::string_view expected, bool value_is_event) {
  std::vector<Entry> entries;
  while (!trim(text).empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view item = trim(text.substr(0, comma));
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    const std::size_t eq = item.find('=');
    Entry e{item, trim(item.substr(0, eq)), eq == std::string_view::npos ? std::string_view{} : trim(item.substr(eq + 1))};
    if (eq == std::string_view::npos || !isDeviceName(e.key) || !isIdentifier(e.value) ||
        (value_is_event && e.value.substr(0, 2) != "e_"))
      throw core::Error("property " + std::string(property) + ", entry '" + std::string(item) + "': expected " +
                        std::string(expected));
    for (const Entry& other : entries)
      if (other.key == e.key || (!value_is_event && other.value == e.value))
        throw core::Error("property " + std::string(property) + ", entry '" + std::string(item) + "': " +
                          (other.key == e.key ? "the name '" + std::string(e.key) + "' is mapped twice"
                                              : "the port '" + std::string(e.value) + "' is mapped twice"));
    entries.push_back(e);
  }
  return entries;
}

// A message's 3x4 matrix as a KDL frame (toIgtlTransform is the way back).
KDL::Frame toFrame(const igtl::Transform& t) {
  const auto& m = t.matrix;
  return KDL::Frame(KDL::Rotation(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]),
                    KDL::Vector(m[0][3], m[1][3], m[2][3]));
}

constexpr const char* kMappingForm = "DEVICE=port (a device name of 1 to 20 printable characters, a port name of "
                                     "letters, digits and '_'), entries separated by ','";
constexpr const char* kRequestForm = "KEY=e_event (a key of 1 to 20 printable characters, an event name starting "
                                     "with e_), entries separated by ','";

}  // namespace

IgtlBridge::IgtlBridge(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "OpenIGTLink bridge to a navigation program (3D Slicer, PLUS): transforms, plans, requests, "
                "images, task state"),
      scratch_(std::make_unique<igtl::Message>()) {
  addPort(plan_);
  addPort(task_state_);
  addEventPort(input_events_);
  addProperty(role_);
  addProperty(host_);
  addProperty(port_.range(0, 65535));
  addProperty(send_period_.range(1e-3, 3600.0));
  addProperty(peer_timeout_.range(0.0, 3600.0));
  addProperty(max_message_bytes_.range(static_cast<int>(igtl::kHeaderSize), 1 << 28));
  addProperty(send_transforms_);
  addProperty(receive_transforms_);
  addProperty(plan_device_);
  addProperty(requests_);
  addProperty(images_);
  addProperty(send_strings_);
  addProperty(received_messages_.readOnly());
  addProperty(sent_messages_.readOnly());
  addProperty(dropped_messages_.readOnly());
  addProperty(dropped_reason_.readOnly());
  addOperation("localPort", &IgtlBridge::localPort, this,
               "the TCP port of a configured bridge (a server's bound port: the ephemeral one when port is 0)",
               core::ExecutionThread::Client);
  addOperation("pendingMessages",
               std::function<int()>([this] { return link_ ? static_cast<int>(link_->outgoing.size()) : 0; }),
               "messages the update queued that the link thread has not written to the peer yet (a lockstep run "
               "that must not outpace its peer waits for 0)",
               core::ExecutionThread::Client);
}

IgtlBridge::~IgtlBridge() {
  if (link_) link_->stop();
}

int IgtlBridge::localPort() {
  if (!link_) throw core::Error("component '" + name() + "': localPort needs a configured bridge");
  return link_->localPort();
}

void IgtlBridge::removeMappedPorts() {
  for (auto& s : send_) removePort(*s.port);
  for (auto& r : receive_) removePort(*r.port);
  for (auto& i : image_ports_) removePort(*i.port);
  for (auto& t : strings_) removePort(*t.port);
  strings_.clear();
  send_.clear();
  receive_.clear();
  image_ports_.clear();
  requests_map_.clear();
}

bool IgtlBridge::parseMappings() {
  // A mapped port name must be new: a port of that name (taskState, plan, ...) has another type
  // or direction, or is mapped already.
  const auto fresh = [&](std::string_view property, const Entry& e, std::string_view wanted) {
    if (const core::PortBase* p = findPort(std::string(e.value)))
      throw core::Error("property " + std::string(property) + ", entry '" + std::string(e.text) +
                        "': the port '" + std::string(e.value) + "' exists already (a " + std::string(p->type().name) +
                        " " + (p->direction() == core::PortDirection::Input ? "in" : "out") +
                        "-port); expected a new port name for a " + std::string(wanted));
  };
  for (const Entry& e : splitMapping("send_transforms", send_transforms_(), kMappingForm, false)) {
    fresh("send_transforms", e, "KDL.Frame in-port");
    send_.push_back({std::string(e.key), std::make_unique<core::InputPort<KDL::Frame>>(
                                             std::string(e.value), "pose sent as TRANSFORM " + std::string(e.key) + ", world", "m")});
    addPort(*send_.back().port);
  }
  for (const Entry& e : splitMapping("receive_transforms", receive_transforms_(), kMappingForm, false)) {
    fresh("receive_transforms", e, "KDL.Frame out-port");
    receive_.push_back({std::string(e.key), std::make_unique<core::OutputPort<KDL::Frame>>(
                                                std::string(e.value), "TRANSFORM " + std::string(e.key) + " received", "m")});
    addPort(*receive_.back().port);
  }
  for (const Entry& e : splitMapping("images", images_(), kMappingForm, false)) {
    fresh("images", e, "Imaging.GrayImage in-port");
    image_ports_.push_back({std::string(e.key), std::make_unique<core::InputPort<types::GrayImage>>(
                                                    std::string(e.value), "image sent as IMAGE " + std::string(e.key), "m")});
    addPort(*image_ports_.back().port);
  }
  for (const Entry& e : splitMapping("send_strings", send_strings_(), kMappingForm, false)) {
    fresh("send_strings", e, "string in-port");
    strings_.push_back({std::string(e.key), std::make_unique<core::InputPort<std::string>>(
                                                std::string(e.value), "line sent as STRING " + std::string(e.key), "")});
    addPort(*strings_.back().port);
  }
  line_.reserve(kLineCapacity);
  for (const Entry& e : splitMapping("requests", requests_(), kRequestForm, true))
    requests_map_.push_back({std::string(e.key), std::string(e.value)});
  if (!plan_device_().empty() && !isDeviceName(plan_device_()))
    throw core::Error("property plan_device, entry '" + plan_device_() +
                      "': expected a device name of 1 to 20 printable characters (no '=' or ',')");
  return true;
}

bool IgtlBridge::configureHook() {
  removeMappedPorts();
  link_.reset();
  if (role_() != "server" && role_() != "client")
    return refuse("property role, entry '" + role_() + "': expected \"server\" or \"client\"");
  try {
    parseMappings();
    IgtlLinkOptions options;
    options.server = role_() == "server";
    options.host = host_();
    options.port = static_cast<std::uint16_t>(port_());
    options.max_body = static_cast<std::size_t>(max_message_bytes_()) - igtl::kHeaderSize;
    options.peer_timeout = peer_timeout_();
    for (const Image& image : image_ports_) options.image_devices.push_back(image.device);
    link_ = std::make_unique<IgtlLink>(options);
  } catch (const std::exception& e) {
    removeMappedPorts();
    return refuse(e.what());
  }
  return true;
}

bool IgtlBridge::startHook() {
  seen_connections_ = link_->connections();
  seen_losses_ = link_->losses();
  next_send_ns_ = now().count();
  have_state_ = false;
  link_->start();
  return true;
}

void IgtlBridge::stopHook() { link_->stop(); }

void IgtlBridge::cleanupHook() {
  link_.reset();
  removeMappedPorts();
}

void IgtlBridge::drop(DropReason reason) noexcept {
  ++own_drops_;
  dropped_reason_.setFromOwner(std::string(dropReasonName(reason)));  // short: inline storage, no allocation
}

void IgtlBridge::queue(const IgtlOutMessage& message) noexcept {
  if (message.size == 0) return;
  if (!link_->outgoing.push(message)) drop(DropReason::SendFull);
}

void IgtlBridge::dispatch(const igtl::Message& m) noexcept {
  const std::string_view device = m.device.view();
  switch (m.type) {
    case igtl::MessageType::Transform:
      for (auto& r : receive_)
        if (r.device == device) {
          r.port->write(toFrame(m.transform));
          ++used_;
          return;
        }
      break;
    case igtl::MessageType::Point:
      if (!plan_device_().empty() && device == plan_device_()) {
        // A surgical plan is whole or not at all: one cut to the list's capacity would reach the
        // chart as if complete.
        if (m.points.total > m.points.count) {
          drop(DropReason::PlanTooLong);
          return;
        }
        types::PointList list;
        for (std::size_t k = 0; k < m.points.count; ++k) {
          const igtl::Point& p = m.points.points[k];
          list.add(p.name.view(), p.group.view(), KDL::Vector(p.position[0], p.position[1], p.position[2]));
        }
        plan_.write(list);
        ++used_;
        return;
      }
      break;
    case igtl::MessageType::String:
      if (device == "Request") {
        for (const Request& r : requests_map_)
          if (r.key == m.text.view()) {
            emitEvent(r.event);
            ++used_;
            return;
          }
        drop(DropReason::Unmapped);
        return;
      }
      break;
    case igtl::MessageType::Status: break;  // no STATUS is mapped
  }
  drop(DropReason::UnknownDevice);
}

void IgtlBridge::sendPeriodic(std::uint64_t stamp) noexcept {
  IgtlOutMessage out;
  for (auto& s : send_) {
    KDL::Frame pose;
    if (s.port->read(pose) == core::FlowStatus::NoData) continue;
    out.size = static_cast<std::uint32_t>(igtl::encodeTransform(s.device, toIgtlTransform(pose), stamp, out.bytes));
    queue(out);
  }
  for (std::size_t i = 0; i < image_ports_.size(); ++i) {
    // Only an image not sent yet, read straight into the link's buffer (64 KiB copied once per
    // send period at most); the link thread encodes it.
    IgtlImage& slot = link_->image(i).back();
    if (image_ports_[i].port->readNew(slot.image) != core::FlowStatus::NewData) continue;
    slot.timestamp = stamp;
    link_->image(i).publish();
  }
}

bool IgtlBridge::reportLink() noexcept {
  // Connection k comes before loss k: emit them in that order.
  const std::uint64_t connections = link_->connections(), losses = link_->losses();
  bool connected = false;
  while (seen_connections_ < connections || seen_losses_ < losses) {
    if (seen_losses_ < seen_connections_ && seen_losses_ < losses) {
      ++seen_losses_;
      emitEvent("e_igtl_peer_lost");
    } else if (seen_connections_ < connections) {
      ++seen_connections_;
      emitEvent("e_igtl_connected");
      connected = true;
    } else {
      break;
    }
  }
  return connected && seen_losses_ == seen_connections_ - 1;  // and that peer is still there
}

void IgtlBridge::updateCounters() noexcept {
  const std::uint64_t link_drops = link_->droppedCount();
  if (link_drops != seen_link_drops_) {
    seen_link_drops_ = link_drops;
    dropped_reason_.setFromOwner(std::string(dropReasonName(link_->lastDrop())));
  }
  received_messages_.setFromOwner(used_);
  sent_messages_.setFromOwner(static_cast<int>(link_->sentCount()));
  dropped_messages_.setFromOwner(static_cast<int>(link_drops) + own_drops_);
}

void IgtlBridge::updateHook() {
  igtl::Message& message = *scratch_;
  for (std::size_t n = 0; n < IgtlLink::kQueue && link_->received.pop(message); ++n) dispatch(message);

  // A new peer gets the task state at once (what was queued before it connected was discarded).
  const bool new_peer = reportLink();
  const std::uint64_t stamp = igtl::wireTimestamp(static_cast<std::uint64_t>(now().count()));
  IgtlOutMessage out;
  core::TaskState state;
  const bool changed =
      task_state_.readNew(state) == core::FlowStatus::NewData && (!have_state_ || !(state == last_state_));
  if (changed) {
    last_state_ = state;
    have_state_ = true;
  }
  if (changed || (new_peer && have_state_)) {
    out.size = static_cast<std::uint32_t>(igtl::encodeStatus("TaskState", 1, 0, "", last_state_.path.view(), stamp, out.bytes));
    queue(out);
  }
  core::Event event;
  while (input_events_.readNew(event) == core::FlowStatus::NewData) {
    out.size = static_cast<std::uint32_t>(igtl::encodeString("Event", event.name.view(), stamp, out.bytes));
    queue(out);
  }
  for (SendString& s : strings_) {
    if (s.port->readNew(line_) != core::FlowStatus::NewData) continue;
    out.size = static_cast<std::uint32_t>(igtl::encodeString(s.device, line_, stamp, out.bytes));
    queue(out);
  }
  const std::int64_t t = now().count();
  if (t >= next_send_ns_) {
    sendPeriodic(stamp);
    const std::int64_t period = toNs(send_period_());
    next_send_ns_ += period;
    if (next_send_ns_ <= t) next_send_ns_ = t + period;  // no burst after a stall
  }
  updateCounters();
}

}  // namespace cobra::bridges
