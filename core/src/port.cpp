#include "cobra/core/port.hpp"

#include <algorithm>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/transport.hpp"

namespace cobra::core {

PortBase::PortBase(std::string name, std::string doc, std::string unit, PortDirection direction, const TypeInfo& type)
    : name_(std::move(name)), doc_(std::move(doc)), unit_(std::move(unit)), direction_(direction), type_(&type) {
  if (name_.empty() || name_.find_first_of(". \t\n") != std::string::npos)
    throw Error("port name '" + name_ + "' must be non-empty without '.' or spaces");
}

PortBase::~PortBase() = default;

std::string PortBase::fullName() const { return owner_ ? owner_->name() + "." + name_ : name_; }

std::vector<std::shared_ptr<ChannelBase>> PortBase::connections() const {
  std::lock_guard lock(links_mutex_);
  return links_;
}

bool PortBase::connected() const {
  std::lock_guard lock(links_mutex_);
  return !links_.empty();
}

bool PortBase::connectedTo(const PortBase& other) const {
  std::lock_guard lock(links_mutex_);
  return std::any_of(links_.begin(), links_.end(), [&](const auto& c) {
    return &c->writer() == &other || &c->reader() == &other || c->peer() == &other;
  });
}

void PortBase::disconnect() {
  for (const auto& channel : connections()) unlinkChannel(channel);
}

void PortBase::changeBetweenSteps(const std::function<void()>& change) {
  if (owner_ != nullptr) owner_->runBetweenSteps(change);
  else change();
}

void PortBase::notifyNewData() noexcept {
  if (owner_ != nullptr) {
    owner_->activity().trigger();
  } else if (new_data_flag_ != nullptr) {
    new_data_flag_->store(true, std::memory_order_release);
    new_data_flag_->notify_one();  // a transport's sending thread waits on it; no waiter: one load
  }
}

void linkChannel(const std::shared_ptr<ChannelBase>& channel) {
  PortBase& reader = channel->reader();
  PortBase& writer = channel->writer();
  // Reader first: a writer never pushes into a channel nobody will read.
  reader.changeBetweenSteps([&] { reader.attachChannel(*channel); });
  {
    std::lock_guard lock(reader.links_mutex_);
    reader.links_.push_back(channel);
  }
  writer.changeBetweenSteps([&] { writer.attachChannel(*channel); });
  std::lock_guard lock(writer.links_mutex_);
  writer.links_.push_back(channel);
}

void unlinkChannel(const std::shared_ptr<ChannelBase>& channel_ref) {
  // A copy: `channel_ref` may be an element of a list erased below, and a transport's end held by
  // the channel must outlive the ports' locks taken here (it may own one of the ports).
  const std::shared_ptr<ChannelBase> channel = channel_ref;
  PortBase& reader = channel->reader();
  PortBase& writer = channel->writer();
  // A transport's threads stop using the end's hidden port before it loses the channel.
  if (TransportEnd* end = channel->transportEnd()) end->close();
  // Writer first: once it no longer pushes, the reader can let go safely.
  writer.changeBetweenSteps([&] { writer.detachChannel(*channel); });
  reader.changeBetweenSteps([&] { reader.detachChannel(*channel); });
  for (PortBase* port : {&writer, &reader}) {
    std::lock_guard lock(port->links_mutex_);
    std::erase(port->links_, channel);
  }
}

void throwConnectionError(const PortBase& output, const PortBase& input, const std::string& why) {
  throw Error("cannot connect " + output.fullName() + " (" + std::string(output.type().name) + ") to " +
              input.fullName() + " (" + std::string(input.type().name) + "): " + why);
}

void checkConnectable(const PortBase& output, const PortBase& input) {
  if (output.direction() != PortDirection::Output)
    throwConnectionError(output, input, output.fullName() + " is an input port; the first port must be an output");
  if (input.direction() != PortDirection::Input)
    throwConnectionError(output, input, input.fullName() + " is an output port; the second port must be an input");
  if (output.connectedTo(input)) throwConnectionError(output, input, "they are already connected");
  for (const PortBase* port : {&output, &input})
    if (port->connections().size() >= PortBase::kMaxConnections)
      throwConnectionError(output, input,
                           port->fullName() + " already has " + std::to_string(PortBase::kMaxConnections) +
                               " connections, the most a port can have");
}

void connectPorts(PortBase& output, PortBase& input, ConnPolicy policy) {
  auto* typed_output = dynamic_cast<OutputPortBase*>(&output);
  if (typed_output == nullptr) {
    checkConnectable(output, input);  // reports the direction problem
    throwConnectionError(output, input, "the first port must be an output");
  }
  if (policy.transport.empty()) {
    typed_output->connectTo(input, policy);
    return;
  }
  checkConnectable(output, input);
  if (output.type().id != input.type().id)
    throwConnectionError(output, input,
                         "the types differ (" + std::string(output.type().name) + " vs " +
                             std::string(input.type().name) + "); connect ports of the same type");
  try {
    const std::shared_ptr<Transport> transport = TransportRegistry::get(policy.transport);
    transport->check(policy);
    // Reader's end first, so that the writer's end finds its reader when it is discovered.
    auto* typed_input = dynamic_cast<InputPortBase*>(&input);
    if (typed_input == nullptr) throw Error("the second port must be a typed input port");
    transport->makeReaderEnd(*typed_input, policy, &output);
    transport->makeWriterEnd(*typed_output, policy, &input);
  } catch (const std::exception& e) {
    disconnectPorts(output, input);  // the end made before the failure
    throwConnectionError(output, input, e.what());
  }
}

bool disconnectPorts(PortBase& output, PortBase& input) {
  bool found = false;
  for (const auto& channel : output.connections()) {
    if (&channel->reader() == &input || channel->peer() == &input) {
      unlinkChannel(channel);
      found = true;
    }
  }
  for (const auto& channel : input.connections()) {
    if (channel->peer() == &output) {
      unlinkChannel(channel);
      found = true;
    }
  }
  return found;
}

}  // namespace cobra::core
