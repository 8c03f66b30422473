#pragma once
/// @file
/// Read-only snapshots of components, and the registry that owns them by name: the API the
/// console, deployer, linter and studio build on.

#include <memory>
#include <string>
#include <unordered_map>
#include <string_view>
#include <vector>

#include "cobra/core/component.hpp"

namespace cobra::core {

struct ConnectionInfo {
  std::string peer;    ///< "Component.port" at the other end
  std::string policy;  ///< "data", "buffer(8)", "circular(8)"
};

struct PortInfo {
  std::string name;
  PortDirection direction;
  std::string type;
  DataKind kind;
  std::string unit;
  std::string doc;
  bool event_port;
  std::vector<ConnectionInfo> connections;
};

struct PropertyInfo {
  std::string name;
  std::string type;
  std::string value;
  std::string unit;
  std::string doc;
  std::string range;  ///< "" when unrestricted
  bool read_only;
};

struct OperationInfo {
  std::string name;
  std::string signature;
  std::string doc;
  ExecutionThread thread;
};

struct ComponentInfo {
  std::string name;
  Role role;
  std::string doc;
  State state;
  std::string activity;
  std::string last_error;
  std::vector<PortInfo> ports;
  std::vector<PropertyInfo> properties;
  std::vector<OperationInfo> operations;
};

/// A consistent snapshot of `component`'s interface and state (thread-safe).
ComponentInfo describe(const Component& component);
/// Multi-line human-readable text of `info`, as the console prints it.
std::string toText(const ComponentInfo& info);

/// Owns components by unique name.
class ComponentRegistry {
 public:
  ComponentRegistry() = default;
  ~ComponentRegistry();
  ComponentRegistry(const ComponentRegistry&) = delete;
  ComponentRegistry& operator=(const ComponentRegistry&) = delete;

  /// Takes ownership. @throws Error when the name is already used.
  Component& add(std::unique_ptr<Component> component);
  /// Constructs a component in place: `registry.make<Gain>("Gain")`.
  template <class C, class... A>
  C& make(A&&... arguments) {
    return static_cast<C&>(add(std::make_unique<C>(std::forward<A>(arguments)...)));
  }
  Component* find(std::string_view name) const;
  /// @throws Error "no component named 'X'; the components are: ...".
  Component& get(std::string_view name) const;
  /// Stops a Running component, disconnects it and destroys it. Returns false if unknown.
  bool remove(std::string_view name);
  /// Components in the order they were added.
  std::vector<Component*> components() const;
  std::vector<ComponentInfo> describeAll() const;

 private:
  std::vector<std::unique_ptr<Component>> components_;  // in the order added
  std::unordered_map<std::string, Component*> by_name_;  // lookups stay O(1) with thousands
};

}  // namespace cobra::core
