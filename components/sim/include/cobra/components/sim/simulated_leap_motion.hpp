#pragma once
/// @file
/// A simulated Leap Motion hand tracker (thesis §5.3.3) above which a scripted surgeon holds his
/// hands: the sim-world side of LeapMotionDriver's `device = "sim:<this component's name>"`.

#include <kdl/frames.hpp>
#include <string>

#include "cobra/components/sim/simulated_device.hpp"
#include "cobra/core/component.hpp"
#include "cobra/sim/leap_motion_device.hpp"

namespace cobra::components {

/// Bridge (the simulated world). Needs a periodic activity: each update takes the true hand poses
/// and advances the tracker (sim::HandTracker: 200 fps, a pyramid field of view, Gaussian noise)
/// by the time since the previous update; the driver takes the frames of earlier steps
/// (sim/device_link.hpp). At configure the device is registered as `sim:<name>`
/// (core::BackendRegistry<fieldbus::HandTrackerDevice>); configure it before its driver.
///
/// Properties: `noise` (m, standard deviation of the position noise per axis), `seed`.
///
/// Ports: in `rightHand`, `leftHand` (m, device frame: z up out of the device, x along its long
/// side; where the surgeon's hands are; no sample yet = no hand above the device).
class SimulatedLeapMotion : public core::Component {
 public:
  explicit SimulatedLeapMotion(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  struct Hand {
    bool present = false;
    KDL::Frame truth;
  };

  core::Property<double> noise_{"noise", 5e-4, "m", "standard deviation of the position noise per axis"};
  core::Property<int> seed_{"seed", 0, "1", "seed of the noise"};
  core::InputPort<KDL::Frame> right_{"rightHand", "true right hand pose, device frame", "m"};
  core::InputPort<KDL::Frame> left_{"leftHand", "true left hand pose, device frame", "m"};

  SimulatedDevice<sim::LeapMotionDevice, fieldbus::HandTrackerDevice> device_;
  Hand right_hand_, left_hand_;
  UpdateInterval interval_;
};

}  // namespace cobra::components
