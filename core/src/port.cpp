#include "cobra/core/port.hpp"

#include <algorithm>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

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
  return std::any_of(links_.begin(), links_.end(),
                     [&](const auto& c) { return &c->writer() == &other || &c->reader() == &other; });
}

void PortBase::disconnect() {
  for (const auto& channel : connections()) unlinkChannel(channel);
}

void PortBase::changeBetweenSteps(const std::function<void()>& change) {
  if (owner_ != nullptr) owner_->runBetweenSteps(change);
  else change();
}

void PortBase::notifyNewData() noexcept {
  if (owner_ != nullptr) owner_->activity().trigger();
  else if (new_data_flag_ != nullptr) new_data_flag_->store(true, std::memory_order_release);
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

void unlinkChannel(const std::shared_ptr<ChannelBase>& channel) {
  PortBase& reader = channel->reader();
  PortBase& writer = channel->writer();
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
  typed_output->connectTo(input, policy);
}

bool disconnectPorts(PortBase& output, PortBase& input) {
  for (const auto& channel : output.connections()) {
    if (&channel->reader() == &input) {
      unlinkChannel(channel);
      return true;
    }
  }
  return false;
}

}  // namespace cobra::core
