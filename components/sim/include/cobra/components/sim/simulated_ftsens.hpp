#pragma once
/// @file
/// A simulated IIT FTSens on a simulated CAN bus (thesis §6.1.2): the sim-world side of the
/// FTSens driver's `bus = "sim:<this component's name>"`.

#include <kdl/frames.hpp>
#include <string>

#include "cobra/components/sim/simulated_device.hpp"
#include "cobra/core/component.hpp"
#include "cobra/sim/ftsens_can_bus.hpp"

namespace cobra::components {

/// Bridge (the simulated world). Needs a periodic activity: each update takes the true wrench and
/// advances the sensor by the time since the previous update, producing the frames of the samples
/// that fell due at the streaming period the driver commanded. At configure the bus is registered
/// as `sim:<name>` (core::BackendRegistry<fieldbus::CanBus>); configure it before its driver. A
/// driver sees the frames of this component's earlier steps (sim/device_link.hpp), whatever the
/// order of the two in the deployment.
///
/// Properties: `address` (the board address the sensor answers to, 0-15), `seed` (its noise),
/// `bias` (N, N·m: the sensor's own offset, sensor frame).
///
/// Ports: in `trueWrench` (N, N·m, sensor frame: the wrench acting on the sensor; none yet = zero).
///
/// Operations (fault injection): `setSilent(bool)` (the sensor stops / resumes sending: a pulled
/// cable), `garbleFrames(n)` (the next n frames carry a flipped bit), `dropSamples(n)` (the next n
/// samples are lost), `overruns()` (frames lost to a full receive queue).
class SimulatedFTSens : public core::Component {
 public:
  explicit SimulatedFTSens(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  sim::FtSensCanBus& bus() const;

  core::Property<int> address_{"address", 0, "1", "the board address the sensor answers to, 0-15"};
  core::Property<int> seed_{"seed", 0, "1", "seed of the sensor's noise"};
  core::Property<KDL::Wrench> bias_{"bias", KDL::Wrench::Zero(), "N, N·m", "the sensor's own offset, sensor frame"};
  core::InputPort<KDL::Wrench> true_wrench_{"trueWrench", "wrench acting on the sensor, sensor frame", "N, N·m"};

  SimulatedDevice<sim::FtSensCanBus, fieldbus::CanBus> device_;
  KDL::Wrench truth_ = KDL::Wrench::Zero();
  UpdateInterval interval_;
};

}  // namespace cobra::components
