#pragma once
/// @file
/// The Leap Motion driver (thesis §5.4.4) as a component, backed by cobra::sim::HandTracker.

#include <kdl/frames.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/sim/hand_tracker.hpp"

namespace cobra::components {

/// Bridge (the thesis calls it a Driver). Needs a periodic activity (the tracker takes frames at
/// 200 fps whatever the period). Every new frame in which a hand is seen publishes its pose:
/// position clamped to `interaction_box`, multiplied by `workspace_scale`, then expressed through
/// `workspace_offset`: out = offset · (R, scale · clamp(p)). A hand not seen keeps its last valid
/// pose on the port.
///
/// Properties: `interaction_box` (x_min, y_min, z_min, x_max, y_max, z_max in m, device frame:
/// z up out of the device, x along its long side), `workspace_offset` (Frame, m), `workspace_scale`
/// (1, > 0), `sim_noise` (m), `sim_seed`.
///
/// Ports: in `simRightHand`, `simLeftHand` (m, device frame; simulation only: where the scripted
/// surgeon's hands are; no sample = no hand); out `measRightPose`, `measLeftPose` (m).
///
/// Events: e_right_hand_lost, e_right_hand_found, e_left_hand_lost, e_left_hand_found.
class LeapMotionDriver : public core::Component {
 public:
  explicit LeapMotionDriver(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  struct Hand {
    bool present = false, seen = false;
    KDL::Frame truth;
  };
  KDL::Frame map(const KDL::Frame& measured) const noexcept;
  void publish(const sim::TrackedHand& tracked, Hand& hand, core::OutputPort<KDL::Frame>& port, const char* lost,
               const char* found) noexcept;

  core::Property<std::vector<double>> box_{"interaction_box",
                                           {-0.1175, -0.0735, 0.0825, 0.1175, 0.0735, 0.3175},
                                           "m",
                                           "x_min, y_min, z_min, x_max, y_max, z_max in the device frame"};
  core::Property<KDL::Frame> offset_{"workspace_offset", KDL::Frame::Identity(), "m",
                                     "applied to every measured pose: changes the reference frame"};
  core::Property<double> scale_{"workspace_scale", 1.0, "1", "multiplies measured positions (sensitivity)"};
  core::Property<double> sim_noise_{"sim_noise", 5e-4, "m", "standard deviation of the simulated position noise"};
  core::Property<int> sim_seed_{"sim_seed", 0, "1", "seed of the simulated noise"};
  core::InputPort<KDL::Frame> sim_right_{"simRightHand", "true right hand pose, device frame (simulation)", "m"};
  core::InputPort<KDL::Frame> sim_left_{"simLeftHand", "true left hand pose, device frame (simulation)", "m"};
  core::OutputPort<KDL::Frame> meas_right_{"measRightPose", "last valid right hand pose", "m"};
  core::OutputPort<KDL::Frame> meas_left_{"measLeftPose", "last valid left hand pose", "m"};

  std::optional<sim::HandTracker> tracker_;
  KDL::Vector box_min_, box_max_;
  Hand right_, left_;
};

}  // namespace cobra::components
