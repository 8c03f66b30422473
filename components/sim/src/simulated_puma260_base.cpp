#include "cobra/components/sim/simulated_puma260_base.hpp"

#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

SimulatedPuma260Base::SimulatedPuma260Base(std::string name, std::string description)
    : Component(std::move(name), core::Role::Bridge, std::move(description)) {
  // Puma260EtherCATMaster's default nest, Corke's nominal Puma pose qn in kinematics/puma260.hpp's DH
  // convention (ASSUMPTION: the arm rests in its nest, the encoder initialisation position, at
  // power-on; the thesis gives no joint vector).
  initial_.set({0.0, 0.7853981633974483, -3.141592653589793, 0.0, 0.7853981633974483, 0.0});
  addProperty(initial_);
  addOperation("injectFault", &SimulatedPuma260Base::injectFault, this,
               "fault: an over-current fault in drive i (the drive goes to Fault, its brake holds the joint)")
      .arg("slave", "1", "slave index, 0-5");
  addOperation("injectWorkingCounterFault", &SimulatedPuma260Base::injectWorkingCounterFault, this,
               "fault: the next n bus cycles come back with a wrong working counter (the last slave skips its "
               "datagram)")
      .arg("cycles", "1", "number of bus cycles, >= 1");
}

void SimulatedPuma260Base::injectFault(int slave) {
  if (device_.get() == nullptr)
    throw std::invalid_argument("the simulated arm exists only while the component is configured");
  if (slave < 0 || slave > 5) throw std::invalid_argument("slave " + std::to_string(slave) + " is not 0-5");
  device_.get()->arm().drive(slave).injectFault(sim::error_code::kOverCurrent);
}

void SimulatedPuma260Base::injectWorkingCounterFault(int cycles) {
  if (device_.get() == nullptr)
    throw std::invalid_argument("the simulated bus exists only while the component is configured");
  if (cycles < 1) throw std::invalid_argument("cycles = " + std::to_string(cycles) + ", expected >= 1");
  device_.get()->injectWorkingCounterFault(cycles);
}

bool SimulatedPuma260Base::initialPosition(std::array<double, 6>& out) {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update steps the arm");
  if (initial_().size() != 6)
    return refuse("property initial_position has " + std::to_string(initial_().size()) +
                  " numbers; give 6 joint angles in rad");
  for (std::size_t i = 0; i < 6; ++i) out[i] = initial_()[i];
  return true;
}

sim::Puma260EtherCatBus& SimulatedPuma260Base::openBus(const std::string& doc, std::unique_ptr<sim::Puma260Plant> plant) {
  return device_.open(*this, doc, std::move(plant));
}

bool SimulatedPuma260Base::startHook() {
  interval_.reset();
  return true;
}

void SimulatedPuma260Base::cleanupHook() { device_.close(); }

}  // namespace cobra::components
