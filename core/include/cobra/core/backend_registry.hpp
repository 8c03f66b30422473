#pragma once
/// @file
/// Backends of device interfaces, by name: how a driver finds the bus or device it talks to
/// from one string property, so that a deployment moves from a simulated device to a real one by
/// changing that property only.
///
/// A backend name is `<scheme>:<address>`. Two kinds of entries fill a registry:
/// - a *factory* for a scheme, added by a package when it loads (`socketcan` -> opens the
///   SocketCAN interface named by the address: `socketcan:can0`);
/// - an *instance* under a full name, added by a component that owns a device while it is
///   configured (the simulated FTSens of sim-world component `FTSensSim` is `sim:FTSensSim`).
/// `open(name)` takes the instance of that name, else asks the scheme's factory; when neither
/// exists it throws an Error that lists every name that does.
///
/// One registry per interface and process. The interface names itself for messages:
/// @code
/// class CanBus {
///  public:
///   static constexpr const char* kBackendKind = "CAN bus";
///   virtual ~CanBus() = default;
///   ...
/// };
/// @endcode
/// Configure-time only: every call may allocate and lock; none belongs in a real-time path.

#include <concepts>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <typeindex>
#include <vector>

#include "cobra/core/error.hpp"

namespace cobra::core {

namespace detail {

/// The type-erased table behind BackendRegistry<I>: one per interface type, process-wide (kept in
/// cobra_core, so that packages loaded with dlopen share it).
class BackendTable {
 public:
  using Factory = std::function<std::shared_ptr<void>(const std::string& address)>;

  static BackendTable& of(std::type_index interface, const char* kind);

  void addFactory(const std::string& scheme, const std::string& doc, const std::string& owner, Factory make);
  /// @return an id for removeInstance.
  std::uint64_t addInstance(const std::string& name, const std::string& doc, std::shared_ptr<void> device);
  void removeInstance(std::uint64_t id) noexcept;
  std::shared_ptr<void> open(const std::string& name) const;
  std::vector<std::string> names() const;
  /// "'sim:FTSensSim' (simulated FTSens), 'socketcan:<address>' (Linux SocketCAN)" or "none".
  std::string listing() const;

 private:
  explicit BackendTable(const char* kind) : kind_(kind) {}
  std::string listingLocked() const;
  struct FactoryEntry {
    std::string doc, owner;
    Factory make;
  };
  struct InstanceEntry {
    std::string doc;
    std::shared_ptr<void> device;
    std::uint64_t id;
  };
  std::string kind_;
  mutable std::mutex mutex_;
  std::map<std::string, FactoryEntry, std::less<>> factories_;    // by scheme
  std::map<std::string, InstanceEntry, std::less<>> instances_;  // by full name
  std::uint64_t next_id_ = 1;
};

}  // namespace detail

/// Keeps an instance registered; removes it when destroyed or reset. Movable, not copyable.
class BackendRegistration {
 public:
  BackendRegistration() = default;
  BackendRegistration(detail::BackendTable& table, std::uint64_t id) : table_(&table), id_(id) {}
  BackendRegistration(BackendRegistration&& other) noexcept : table_(other.table_), id_(other.id_) {
    other.table_ = nullptr;
  }
  BackendRegistration& operator=(BackendRegistration&& other) noexcept {
    if (this != &other) {
      reset();
      table_ = other.table_;
      id_ = other.id_;
      other.table_ = nullptr;
    }
    return *this;
  }
  BackendRegistration(const BackendRegistration&) = delete;
  BackendRegistration& operator=(const BackendRegistration&) = delete;
  ~BackendRegistration() { reset(); }

  void reset() noexcept {
    if (table_ != nullptr) table_->removeInstance(id_);
    table_ = nullptr;
  }
  explicit operator bool() const noexcept { return table_ != nullptr; }

 private:
  detail::BackendTable* table_ = nullptr;
  std::uint64_t id_ = 0;
};

/// The backends of device interface `Interface`.
template <class Interface>
class BackendRegistry {
  static_assert(std::is_polymorphic_v<Interface> && std::has_virtual_destructor_v<Interface>,
                "cobra: BackendRegistry<I>: I must be a device interface with a virtual destructor "
                "(backends are used and deleted through it)");
  static_assert(requires {
    { Interface::kBackendKind } -> std::convertible_to<const char*>;
  }, "cobra: BackendRegistry<I>: I must name itself for messages: static constexpr const char* kBackendKind = \"CAN bus\";");

 public:
  /// Makes a backend from the part of its name after `<scheme>:`. It throws (any std::exception)
  /// with a message saying why the device cannot be opened.
  using Factory = std::function<std::unique_ptr<Interface>(const std::string& address)>;

  /// Adds the factory of `scheme` (letters, digits, '_' and '-'). Adding a scheme again from the
  /// same `owner` replaces it (a package loaded by a second Configurator in the process).
  /// @throws Error when `scheme` is malformed or another owner registered it.
  static void addFactory(const std::string& scheme, const std::string& doc, const std::string& owner, Factory make) {
    table().addFactory(scheme, doc, owner, [make = std::move(make)](const std::string& address) {
      return std::shared_ptr<void>(std::shared_ptr<Interface>(make(address)));
    });
  }

  /// Registers `device` as `name` (`<scheme>:<address>`) until the returned registration is
  /// destroyed. @throws Error when `name` is malformed or taken.
  [[nodiscard]] static BackendRegistration addInstance(const std::string& name, const std::string& doc,
                                                       std::shared_ptr<Interface> device) {
    return {table(), table().addInstance(name, doc, std::shared_ptr<void>(std::move(device)))};
  }

  /// The backend called `name`: the instance of that name, or a new device from the scheme's
  /// factory. @throws Error "no CAN bus backend 'x'; backends that exist: ..." or the factory's
  /// reason, prefixed with the name.
  static std::shared_ptr<Interface> open(const std::string& name) {
    return std::static_pointer_cast<Interface>(table().open(name));
  }

  /// Instance names and `<scheme>:<address>` for factories, sorted.
  static std::vector<std::string> names() { return table().names(); }

 private:
  static detail::BackendTable& table() {
    return detail::BackendTable::of(std::type_index(typeid(Interface)), Interface::kBackendKind);
  }
};

}  // namespace cobra::core
