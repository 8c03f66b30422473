#pragma once
/// @file
/// A simulated Leap Motion hand tracker (thesis §5.3.3) above which a scripted surgeon holds his
/// hands: the sim-world side of LeapMotionDriver's `device = "sim:<this component's name>"`.

#include <kdl/frames.hpp>
#include <string>

#include "cobra/components/sim/scripted_hand.hpp"
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
/// Properties: `noise` (m, standard deviation of the position noise per axis), `seed`;
/// simulation only, for a fault script: `scripted_hands` (bool, default false), `right_hand`,
/// `left_hand` (Frame, m, device frame): while a hand's port has never had data and
/// scripted_hands is true, that hand is above the device and moves toward its property's pose,
/// position and orientation, as a first-order motion (ScriptedHand, time constant 0.1 s: a new
/// pose set by a script is reached the way a hand moves, not in a jump).
///
/// Ports: in `rightHand`, `leftHand` (m, device frame: z up out of the device, x along its long
/// side; where the surgeon's hands are, six DoF; no sample yet and no scripted hands = no hand
/// above the device).
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
    bool from_port = false;  // its port has had data: the script's pose no longer applies
    KDL::Frame truth;
    ScriptedHand scripted;
  };
  void follow(core::InputPort<KDL::Frame>& port, const KDL::Frame& scripted, bool start, double dt, Hand& hand) noexcept;

  core::Property<double> noise_{"noise", 5e-4, "m", "standard deviation of the position noise per axis"};
  core::Property<int> seed_{"seed", 0, "1", "seed of the noise"};
  core::Property<bool> scripted_{"scripted_hands", false, "",
                                 "simulation only: the hands at right_hand / left_hand while their ports have no data"};
  core::Property<KDL::Frame> right_pose_{"right_hand", KDL::Frame(KDL::Vector(0.05, 0, 0.2)), "m",
                                         "simulation only: where the scripted right hand goes, device frame"};
  core::Property<KDL::Frame> left_pose_{"left_hand", KDL::Frame(KDL::Vector(-0.05, 0, 0.2)), "m",
                                        "simulation only: where the scripted left hand goes, device frame"};
  core::InputPort<KDL::Frame> right_{"rightHand", "true right hand pose, device frame", "m"};
  core::InputPort<KDL::Frame> left_{"leftHand", "true left hand pose, device frame", "m"};

  SimulatedDevice<sim::LeapMotionDevice, fieldbus::HandTrackerDevice> device_;
  Hand right_hand_, left_hand_;
  UpdateInterval interval_;
  bool started_ = false;
};

}  // namespace cobra::components
