#include "cobra/core/backend_registry.hpp"

#include <algorithm>
#include <cctype>

namespace cobra::core::detail {
namespace {

constexpr const char* kHint =
    " (a sim-world component registers its device as sim:<component name> when it is configured; a package "
    "adds the schemes of real devices when it loads)";

bool validScheme(const std::string& scheme) {
  return !scheme.empty() && std::all_of(scheme.begin(), scheme.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || c == '_' || c == '-';
  });
}

/// Splits `<scheme>:<address>`; false when either part is missing or the scheme is malformed.
bool split(const std::string& name, std::string& scheme, std::string& address) {
  const std::size_t colon = name.find(':');
  if (colon == std::string::npos) return false;
  scheme = name.substr(0, colon);
  address = name.substr(colon + 1);
  return validScheme(scheme) && !address.empty();
}

}  // namespace

BackendTable& BackendTable::of(std::type_index interface, const char* kind) {
  // Never destroyed: registrations held by static objects may end after main returns.
  static auto* mutex = new std::mutex;
  static auto* tables = new std::map<std::type_index, std::unique_ptr<BackendTable>>;
  std::lock_guard lock(*mutex);
  auto& table = (*tables)[interface];
  if (!table) table.reset(new BackendTable(kind));
  return *table;
}

void BackendTable::addFactory(const std::string& scheme, const std::string& doc, const std::string& owner,
                              Factory make) {
  if (!validScheme(scheme))
    throw Error(kind_ + " backend scheme '" + scheme + "' (from " + owner +
                "): expected letters, digits, '_' or '-', as in 'socketcan'");
  std::lock_guard lock(mutex_);
  auto it = factories_.find(scheme);
  if (it != factories_.end() && it->second.owner != owner)
    throw Error(owner + " registers the " + kind_ + " backend scheme '" + scheme + "', which " + it->second.owner +
                " registered already; scheme names must be unique");
  factories_[scheme] = FactoryEntry{doc, owner, std::move(make)};
}

std::uint64_t BackendTable::addInstance(const std::string& name, const std::string& doc, std::shared_ptr<void> device) {
  std::string scheme, address;
  if (!split(name, scheme, address))
    throw Error("'" + name + "' is not a " + kind_ + " backend name: expected <scheme>:<address>, e.g. sim:FTSensSim");
  if (!device) throw Error(kind_ + " backend '" + name + "': no device given");
  std::lock_guard lock(mutex_);
  if (auto it = instances_.find(name); it != instances_.end())
    throw Error("a " + kind_ + " backend named '" + name + "' exists already (" + it->second.doc +
                "); backend names are unique in a process: give the device's component another name");
  const std::uint64_t id = next_id_++;
  instances_.emplace(name, InstanceEntry{doc, std::move(device), id});
  return id;
}

void BackendTable::removeInstance(std::uint64_t id) noexcept {
  std::shared_ptr<void> device;  // released after the lock: a device's destructor may take time
  std::lock_guard lock(mutex_);
  for (auto it = instances_.begin(); it != instances_.end(); ++it) {
    if (it->second.id == id) {
      device = std::move(it->second.device);
      instances_.erase(it);
      return;
    }
  }
}

std::shared_ptr<void> BackendTable::open(const std::string& name) const {
  std::string scheme, address;
  Factory make;
  {
    std::lock_guard lock(mutex_);
    if (auto it = instances_.find(name); it != instances_.end()) return it->second.device;
    if (!split(name, scheme, address)) {
      throw Error("'" + name + "' is not a " + kind_ + " backend name: expected <scheme>:<address>; backends that exist: " +
                  listingLocked() + kHint);
    }
    auto factory = factories_.find(scheme);
    if (factory == factories_.end())
      throw Error("no " + kind_ + " backend '" + name + "'; backends that exist: " + listingLocked() + kHint);
    make = factory->second.make;
  }
  std::shared_ptr<void> device;
  try {
    device = make(address);
  } catch (const std::exception& e) {
    throw Error(kind_ + " backend '" + name + "': " + e.what());
  }
  if (!device) throw Error(kind_ + " backend '" + name + "': its factory returned no device");
  return device;
}

std::vector<std::string> BackendTable::names() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  for (const auto& [name, entry] : instances_) out.push_back(name);
  for (const auto& [scheme, entry] : factories_) out.push_back(scheme + ":<address>");
  std::sort(out.begin(), out.end());
  return out;
}

std::string BackendTable::listing() const {
  std::lock_guard lock(mutex_);
  return listingLocked();
}

std::string BackendTable::listingLocked() const {
  std::vector<std::string> items;
  for (const auto& [name, entry] : instances_) items.push_back("'" + name + "' (" + entry.doc + ")");
  for (const auto& [scheme, entry] : factories_)
    items.push_back("'" + scheme + ":<address>' (" + entry.doc + ", from " + entry.owner + ")");
  std::sort(items.begin(), items.end());
  if (items.empty()) return "none";
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

}  // namespace cobra::core::detail
