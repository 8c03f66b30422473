#pragma once
/// @file
/// What a sim-world component does with the simulated device it provides: makes it at configure,
/// links it to the component's clock and registers it as `sim:<component name>` in
/// core::BackendRegistry<Interface>, where a driver finds it through its `bus` or `device`
/// property; unplugs and unregisters it at cleanup and destruction.

#include <memory>
#include <string>
#include <type_traits>

#include "cobra/core/activity.hpp"
#include "cobra/core/backend_registry.hpp"
#include "cobra/core/component.hpp"

namespace cobra::components {

/// `Device` is a cobra::sim device (with `link()`, a sim::DeviceLink) implementing `Interface`.
template <class Device, class Interface>
class SimulatedDevice {
  static_assert(std::is_base_of_v<Interface, Device>,
                "cobra: SimulatedDevice<Device, Interface>: Device must implement the interface drivers use");

 public:
  SimulatedDevice() = default;
  SimulatedDevice(const SimulatedDevice&) = delete;
  SimulatedDevice& operator=(const SimulatedDevice&) = delete;
  ~SimulatedDevice() { close(); }

  /// Makes the device from `args`, stamps its values with `owner`'s clock and registers it.
  /// @throws std::invalid_argument (bad model) or core::Error (the name is taken).
  template <class... Args>
  Device& open(core::Component& owner, const std::string& doc, Args&&... args) {
    close();
    auto device = std::make_shared<Device>(std::forward<Args>(args)...);
    device->link().attach([&owner] { return static_cast<std::int64_t>(owner.now().count()); });
    try {
      registration_ = core::BackendRegistry<Interface>::addInstance(name(owner), doc, device);
    } catch (...) {
      device->link().detach();
      throw;
    }
    device_ = std::move(device);
    return *device_;
  }

  /// Unregisters the device and unplugs it: a driver still holding it sees a link down.
  void close() noexcept {
    registration_.reset();
    if (device_) device_->link().detach();
    device_.reset();
  }

  Device* get() const noexcept { return device_.get(); }
  static std::string name(const core::Component& owner) { return "sim:" + owner.name(); }

 private:
  std::shared_ptr<Device> device_;
  core::BackendRegistration registration_;
};

/// Seconds since a component's previous update: what a sim-world component advances its device
/// by (the activity's period at the first update after start). Allocation-free.
class UpdateInterval {
 public:
  void reset() noexcept { last_ns_ = -1; }
  double next(const core::Component& component) noexcept {
    const std::int64_t now_ns = component.now().count();
    const double dt = last_ns_ < 0 ? std::chrono::duration<double>(component.activity().period()).count()
                                   : static_cast<double>(now_ns - last_ns_) * 1e-9;
    last_ns_ = now_ns;
    return dt;
  }

 private:
  std::int64_t last_ns_ = -1;
};

}  // namespace cobra::components
