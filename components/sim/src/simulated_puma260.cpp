#include "cobra/components/sim/simulated_puma260.hpp"

#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

SimulatedPuma260::SimulatedPuma260(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "simulated Puma 260 with six CiA 402 drives on a simulated EtherCAT bus (thesis §6.1.1), for "
                "Puma260EtherCATMaster bus = sim:<name>") {
  // Corke's nominal Puma pose qn in kinematics/puma260.hpp's DH convention (ASSUMPTION: the arm
  // rests in its nest at power-on; the thesis gives no joint vector).
  initial_.set({0.0, 0.7853981633974483, -3.141592653589793, 0.0, 0.7853981633974483, 0.0});
  addProperty(initial_);
  addPort(true_position_);
  true_position_.setDataSample(KDL::JntArray(6));
  addOperation("injectFault", &SimulatedPuma260::injectFault, this,
               "fault: an over-current fault in drive i (the drive goes to Fault)")
      .arg("slave", "1", "slave index, 0-5");
  addOperation("injectWorkingCounterFault", &SimulatedPuma260::injectWorkingCounterFault, this,
               "fault: the next n bus cycles come back with a wrong working counter (the last slave skips its "
               "datagram)")
      .arg("cycles", "1", "number of bus cycles, >= 1");
}

void SimulatedPuma260::injectWorkingCounterFault(int cycles) {
  if (device_.get() == nullptr)
    throw std::invalid_argument("the simulated bus exists only while the component is configured");
  if (cycles < 1) throw std::invalid_argument("cycles = " + std::to_string(cycles) + ", expected >= 1");
  device_.get()->injectWorkingCounterFault(cycles);
}

void SimulatedPuma260::injectFault(int slave) {
  if (device_.get() == nullptr)
    throw std::invalid_argument("the simulated arm exists only while the component is configured");
  if (slave < 0 || slave > 5) throw std::invalid_argument("slave " + std::to_string(slave) + " is not 0-5");
  device_.get()->arm().drive(slave).injectFault(sim::error_code::kOverCurrent);
}

bool SimulatedPuma260::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update steps the arm");
  if (initial_().size() != 6)
    return refuse("property initial_position has " + std::to_string(initial_().size()) +
                  " numbers; give 6 joint angles in rad");
  std::array<double, 6> initial{};
  for (std::size_t i = 0; i < 6; ++i) initial[i] = initial_()[i];
  try {
    device_.open(*this, "simulated Puma 260 drives of component '" + name() + "'", sim::Puma260ArmModel::defaults(),
                 initial);
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  return true;
}

bool SimulatedPuma260::startHook() {
  interval_.reset();
  return true;
}

void SimulatedPuma260::cleanupHook() { device_.close(); }

void SimulatedPuma260::updateHook() {
  const double dt = interval_.next(*this);
  sim::Puma260EtherCatBus& bus = *device_.get();
  bus.step(dt);
  for (int i = 0; i < 6; ++i) out_(static_cast<unsigned>(i)) = bus.arm().drive(i).position();
  true_position_.write(out_);
}

}  // namespace cobra::components
