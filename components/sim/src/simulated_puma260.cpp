#include "cobra/components/sim/simulated_puma260.hpp"

#include <stdexcept>

namespace cobra::components {

SimulatedPuma260::SimulatedPuma260(std::string name)
    : SimulatedPuma260Base(std::move(name),
                           "simulated Puma 260 with six CiA 402 drives on a simulated EtherCAT bus (thesis §6.1.1), "
                           "for Puma260EtherCATMaster bus = sim:<name>") {
  addPort(true_position_);
  true_position_.setDataSample(KDL::JntArray(6));
}

bool SimulatedPuma260::configureHook() {
  std::array<double, 6> initial{};
  if (!initialPosition(initial)) return false;
  try {
    openBus("simulated Puma 260 drives of component '" + name() + "'",
            std::make_unique<sim::Puma260Arm>(sim::Puma260ArmModel::defaults(), initial));
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  return true;
}

void SimulatedPuma260::updateHook() {
  stepBus();
  for (int i = 0; i < 6; ++i) out_(static_cast<unsigned>(i)) = bus().arm().drive(i).position();
  true_position_.write(out_);
}

}  // namespace cobra::components
