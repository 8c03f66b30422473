#pragma once
/// @file
/// What the two sim-world components of the Puma 260 share (SimulatedPuma260: the analytic arm;
/// Puma260World: the MuJoCo world): the simulated EtherCAT bus registered as `sim:<name>`, the
/// power-on position, the fault-injection operations and the update interval.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "cobra/components/sim/simulated_device.hpp"
#include "cobra/core/component.hpp"
#include "cobra/sim/puma260_ethercat_bus.hpp"

namespace cobra::components {

/// Bridge base. Property `initial_position` (6 joint angles at power-on, rad; default
/// Puma260EtherCATMaster's default nest, Corke's nominal pose qn). Operations `injectFault(i)`
/// (over-current fault in drive i, 0-5) and `injectWorkingCounterFault(n)` (the next n bus cycles
/// come back with a wrong working counter: the last slave does not process its datagram).
class SimulatedPuma260Base : public core::Component {
 protected:
  SimulatedPuma260Base(std::string name, std::string description);

  /// The checks every configure makes (a periodic activity, 6 initial angles) and the angles.
  /// @return false after `refuse` with the reason.
  bool initialPosition(std::array<double, 6>& out);
  /// Registers a bus on `plant` as `sim:<name>`. @throws std::invalid_argument for a bad plant.
  sim::Puma260EtherCatBus& openBus(const std::string& doc, std::unique_ptr<sim::Puma260Plant> plant);
  sim::Puma260EtherCatBus& bus() const { return *device_.get(); }
  /// Steps the bus (its drives and arm) by the time since the previous update.
  void stepBus() noexcept { device_.get()->step(interval_.next(*this)); }

  bool startHook() override;
  void cleanupHook() override;

 private:
  void injectFault(int slave);
  void injectWorkingCounterFault(int cycles);

  core::Property<std::vector<double>> initial_{"initial_position", {}, "rad", "6 joint angles at power-on"};
  SimulatedDevice<sim::Puma260EtherCatBus, fieldbus::Cia402Bus> device_;
  UpdateInterval interval_;
};

}  // namespace cobra::components
