#include "cobra/core/transport.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <mutex>

#include "cobra/core/error.hpp"
#include "cobra/core/port.hpp"

namespace cobra::core {
namespace {

struct Entry {
  std::string doc, owner;
  std::shared_ptr<Transport> transport;
};

struct Registry {
  std::mutex mutex;
  std::map<std::string, Entry, std::less<>> entries;
};

Registry& registry() {
  // Never destroyed: a transport registered by a static object may be removed after main returns.
  static auto* instance = new Registry;
  return *instance;
}

bool validName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || c == '_' || c == '-';
  });
}

std::string listingLocked(const Registry& r) {
  if (r.entries.empty()) return "none are registered (a library registers its transport when it loads, e.g. cobra_dds)";
  std::string out;
  for (const auto& [name, entry] : r.entries)
    out += (out.empty() ? "" : ", ") + ("'" + name + "' (" + entry.doc + ", from " + entry.owner + ")");
  return out;
}

}  // namespace

void attachTransportEnd(PortBase& port, PortBase& hidden, const ConnPolicy& policy,
                        std::shared_ptr<TransportEnd> end, PortBase* peer) {
  const bool writer_end = port.direction() == PortDirection::Output;
  auto* output = dynamic_cast<OutputPortBase*>(writer_end ? &port : &hidden);
  if (output == nullptr || hidden.direction() == port.direction() || hidden.type().id != port.type().id)
    throw Error("transport end of " + port.fullName() + ": its own port " + hidden.fullName() +
                " must be of the opposite direction and the same type (" + std::string(port.type().name) + ")");
  output->connectTo(writer_end ? hidden : port, policy);
  const auto channels = hidden.connections();
  if (channels.size() != 1)
    throw Error("transport end of " + port.fullName() + ": its own port " + hidden.fullName() +
                " must have exactly one connection, has " + std::to_string(channels.size()));
  channels.front()->holdTransportEnd(std::move(end), peer);
}

void TransportRegistry::add(const std::string& name, const std::string& doc, const std::string& owner,
                            std::shared_ptr<Transport> transport) {
  if (!validName(name))
    throw Error("transport name '" + name + "' (from " + owner + "): expected letters, digits, '_' or '-', as in 'dds'");
  if (!transport) throw Error("transport '" + name + "' (from " + owner + "): no transport given");
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  auto it = r.entries.find(name);
  if (it != r.entries.end() && it->second.owner != owner)
    throw Error(owner + " registers the transport '" + name + "', which " + it->second.owner +
                " registered already; transport names must be unique");
  r.entries[name] = Entry{doc, owner, std::move(transport)};
}

bool TransportRegistry::remove(const std::string& name) {
  std::shared_ptr<Transport> removed;  // destroyed after the lock: a transport may take time to stop
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  auto it = r.entries.find(name);
  if (it == r.entries.end()) return false;
  removed = std::move(it->second.transport);
  r.entries.erase(it);
  return true;
}

std::shared_ptr<Transport> TransportRegistry::get(const std::string& name) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  auto it = r.entries.find(name);
  if (it == r.entries.end()) throw Error("unknown transport '" + name + "'; transports: " + listingLocked(r));
  return it->second.transport;
}

std::vector<std::string> TransportRegistry::names() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::vector<std::string> out;
  for (const auto& [name, entry] : r.entries) out.push_back(name);
  return out;
}

void connectToTransport(PortBase& port, const ConnPolicy& policy) {
  const std::string head = "cannot connect " + port.fullName() + " (" + std::string(port.type().name) + ") to ";
  if (policy.transport.empty())
    throw Error(head + "a transport: its connection policy names none (set transport, e.g. \"dds\", and topic)");
  try {
    const std::shared_ptr<Transport> transport = TransportRegistry::get(policy.transport);
    transport->check(policy);
    if (auto* output = dynamic_cast<OutputPortBase*>(&port)) transport->makeWriterEnd(*output, policy, nullptr);
    else if (auto* input = dynamic_cast<InputPortBase*>(&port)) transport->makeReaderEnd(*input, policy, nullptr);
    else throw Error("it is neither a typed output nor a typed input port");
  } catch (const std::exception& e) {
    throw Error(head + policy.transport + " topic '" + policy.topic + "': " + e.what());
  }
}

}  // namespace cobra::core
