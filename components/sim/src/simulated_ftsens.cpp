#include "cobra/components/sim/simulated_ftsens.hpp"

#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

SimulatedFTSens::SimulatedFTSens(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "simulated IIT FTSens on a simulated CAN bus (thesis §6.1.2), for FTSensDriver bus = sim:<name>") {
  addProperty(address_);
  addProperty(seed_);
  addProperty(bias_);
  addPort(true_wrench_);
  addOperation("setSilent", std::function<void(bool)>([this](bool silent) { bus().setSilent(silent); }),
               "fault: the sensor stops (true) or resumes (false) sending, as with a pulled cable")
      .arg("silent", "1", "true: nothing is sent");
  addOperation("garbleFrames", std::function<void(int)>([this](int count) { bus().garbleFrames(count); }),
               "fault: the next frames arrive with a flipped bit (their checksum fails)")
      .arg("count", "1", "number of frames");
  addOperation("dropSamples", std::function<void(int)>([this](int count) { bus().dropSamples(count); }),
               "fault: the next samples are lost on the bus")
      .arg("count", "1", "number of samples");
  addOperation("overruns", std::function<int()>([this] { return static_cast<int>(bus().overruns()); }),
               "frames lost so far because the receive queue was full");
}

sim::FtSensCanBus& SimulatedFTSens::bus() const {
  if (device_.get() == nullptr)
    throw std::invalid_argument("the simulated sensor exists only while the component is configured");
  return *device_.get();
}

bool SimulatedFTSens::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update advances the sensor");
  fieldbus::FtSensCodecConfig codec;
  codec.address = address_();
  sim::ForceTorqueSensorModel sensor = sim::ftSens();
  sensor.bias = bias_();
  try {
    device_.open(*this, "simulated FTSens of component '" + name() + "'", sensor, codec,
                 static_cast<std::uint64_t>(seed_()));
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  truth_ = KDL::Wrench::Zero();
  return true;
}

bool SimulatedFTSens::startHook() {
  interval_.reset();
  return true;
}

void SimulatedFTSens::cleanupHook() { device_.close(); }

void SimulatedFTSens::updateHook() {
  const double dt = interval_.next(*this);
  (void)true_wrench_.read(truth_);
  sim::FtSensCanBus& device = *device_.get();
  device.setTrueWrench(truth_);
  device.advance(dt);
}

}  // namespace cobra::components
