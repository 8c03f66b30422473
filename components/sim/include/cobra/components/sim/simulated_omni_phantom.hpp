#pragma once
/// @file
/// Simulated Phantom Omni haptic master (thesis §4.5.9 OmniPhantom Bridge interface) backed by
/// sim::HapticMaster held by a scripted surgeon's hand.

#include <cstdint>
#include <kdl/frames.hpp>
#include <optional>
#include <string>

#include "cobra/components/sim/scripted_hand.hpp"
#include "cobra/core/component.hpp"
#include "cobra/sim/haptic.hpp"

namespace cobra::components {

/// Bridge component. Frame O = origin_pose_offset · D, where D is the device frame (origin at the
/// centre of the force-feedback workspace); as in the thesis, the offset is applied to every
/// measured pose. Six-DoF pose: the Omni actuates its first three joints only (the position), its
/// gimbal's three joints are passive but measured: the stylus's orientation is the hand's, reached
/// as a first-order motion (ScriptedHand, time constant 0.05 s: a wrist turning, not a jump when
/// a script sets a new orientation); the gimbal's joint limits are not modelled.
///
/// Inputs: `desWrench` (KDL::Wrench, N, N·m, frame O orientation): its force is rendered on the
/// hand (saturated at the device's 3.3 N), its torque is ignored (no actuated wrist); `handTarget`
/// (KDL::Frame, m, frame O; simulation only): where the scripted surgeon pulls the stylus and how
/// he turns it; `handButtons` (int; simulation only): the buttons the surgeon holds.
/// Outputs each update: `measCartPose` (KDL::Frame, m, frame O, position quantised at the device's
/// 0.055 mm), `measTwist` (KDL::Twist, m/s and rad/s, frame O orientation), `statusButtons`
/// (int bitmask: bit 0 = the first (dark grey) stylus button, bit 1 = the second (light grey)),
/// `dissipatedPower` (double, W: what the device's backdrive friction dissipated over the step,
/// the master's D_m for the master side's PassivityLayer.dissipation).
/// Properties: `origin_pose_offset` (Frame, m), `initial_position` (Vector, m, frame D),
/// `hand_motion` (Frame, m, frame D; simulation only: the scripted hand's displacement from
/// initial_position and the stylus's orientation in D, for a fault script to set while
/// handTarget has never had data; identity: the hand holds the stylus still at initial_position).
/// The network bridge's host_address / host_port have no meaning here. updateHook allocates nothing.
class SimulatedOmniPhantom : public core::Component {
 public:
  explicit SimulatedOmniPhantom(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  core::Property<KDL::Frame> origin_pose_offset_{
      "origin_pose_offset", KDL::Frame::Identity(), "m",
      "offset applied to every measured pose (device frame -> output frame)"};
  core::Property<KDL::Vector> initial_position_{"initial_position", KDL::Vector::Zero(), "m",
                                                "stylus position at configure, device frame, inside the workspace"};

  core::Property<KDL::Frame> hand_motion_{
      "hand_motion", KDL::Frame::Identity(), "m",
      "simulation only: the hand's displacement from initial_position and the stylus orientation, device frame"};

  core::InputPort<KDL::Wrench> des_wrench_{"desWrench", "force to render on the hand (torque ignored)", "N, N·m"};
  core::InputPort<KDL::Frame> hand_target_{"handTarget", "simulation only: where the surgeon pulls the stylus", "m"};
  core::InputPort<int> hand_buttons_{"handButtons", "simulation only: buttons the surgeon holds, bitmask", "1"};
  core::OutputPort<KDL::Frame> meas_cart_pose_{"measCartPose", "measured stylus pose", "m"};
  core::OutputPort<KDL::Twist> meas_twist_{"measTwist", "measured stylus twist", "m/s, rad/s"};
  core::OutputPort<int> status_buttons_{"statusButtons", "button bitmask: bit 0 first, bit 1 second button", "1"};
  core::OutputPort<double> dissipated_power_{"dissipatedPower", "power the device's friction dissipated", "W"};

  std::optional<sim::HapticMaster> device_;
  std::int64_t last_update_ns_ = -1;
  ScriptedHand stylus_;  // its orientation: the stylus's, frame D
  KDL::Rotation target_rotation_;  // frame D
  bool hand_target_seen_ = false;
  int buttons_ = 0;
};

}  // namespace cobra::components
