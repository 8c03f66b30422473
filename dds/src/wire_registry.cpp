// The registry of the types the dds transport carries (register_type.hpp).
#include <algorithm>
#include <map>
#include <mutex>

#include "cobra/core/error.hpp"
#include "cobra/core/type_facets.hpp"
#include "cobra/dds/register_type.hpp"

namespace cobra::dds {
namespace detail {
namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::type_index, Binding> bindings;  // nodes never move: findBinding hands out pointers
  std::vector<std::string> names;               // registration order, for messages
};

Registry& registry() {
  static Registry instance;
  return instance;
}

}  // namespace

void addBinding(std::type_index type, Binding binding) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::string name = binding.cobra_type;
  if (r.bindings.try_emplace(type, std::move(binding)).second) r.names.push_back(std::move(name));
}

const Binding* findBinding(std::type_index type) {
  {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    const auto it = r.bindings.find(type);
    if (it != r.bindings.end()) return &it->second;
  }
  // Registered by another module of this process (a package, when this transport is the
  // cobra_dds package): its binding, published process-wide (register_type.hpp).
  return static_cast<const Binding*>(core::TypeFacets::get(type, facet));
}

std::string registeredDdsTypes() {
  std::string text;
  for (const std::string& name : ddsTypes()) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace detail

std::vector<std::string> ddsTypes() {
  detail::Registry& r = detail::registry();
  std::lock_guard lock(r.mutex);
  return r.names;
}

std::string registeredIdl(std::string_view cobra_name) {
  std::string (*idl)() = nullptr;
  std::string dds_type;
  {
    detail::Registry& r = detail::registry();
    std::lock_guard lock(r.mutex);
    const auto it = std::find_if(r.bindings.begin(), r.bindings.end(),
                                 [&](const auto& entry) { return entry.second.cobra_type == cobra_name; });
    if (it == r.bindings.end())
      throw core::Error("no type '" + std::string(cobra_name) + "' is registered for DDS; registered: " +
                        [&] {
                          std::string text;
                          for (const auto& name : r.names) text += (text.empty() ? "" : ", ") + name;
                          return text;
                        }());
    idl = it->second.idl;
    dds_type = it->second.dds_type;
  }
  if (idl == nullptr)
    throw core::Error("'" + std::string(cobra_name) + "' travels as the message " + dds_type +
                      ", not as a record: its IDL is that message's (cobra's are in dds/idl)");
  return idl();
}

// cobra's own types on DDS, from core's list of them (core::BuiltinDataTypes), as script and
// reporting seed their registries: nothing in dds names a type.
void registerBuiltinWires() {
  static std::once_flag once;
  std::call_once(once, [] {
    // cobra's own types: core's one list of them (each has a built-in ROS 2 wire in codec.hpp).
    core::forEachType(core::BuiltinDataTypes{}, [](auto type) { registerDdsType<typename decltype(type)::type>(); });
  });
}

}  // namespace cobra::dds
