#pragma once
/// @file
/// The Leap Motion driver (thesis §5.4.4) as a component, on a cobra::fieldbus::HandTrackerDevice
/// found by name.

#include <kdl/frames.hpp>
#include <memory>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/fieldbus/hand_tracker_device.hpp"

namespace cobra::components {

/// Bridge (the thesis calls it a Driver). Needs a periodic activity (the tracker takes frames at
/// 200 fps whatever the period; each update takes the newest). Every new frame in which a hand is seen publishes its pose:
/// position clamped to `interaction_box`, multiplied by `workspace_scale`, then expressed through
/// `workspace_offset`: out = offset · (R, scale · clamp(p)). A hand not seen keeps its last valid
/// pose on the port.
///
/// Properties: `interaction_box` (x_min, y_min, z_min, x_max, y_max, z_max in m, device frame:
/// z up out of the device, x along its long side), `workspace_offset` (Frame, m), `workspace_scale`
/// (1, > 0), `device` (the tracker, core::BackendRegistry<fieldbus::HandTrackerDevice>:
/// `sim:<component>` for the simulated tracker of that sim-world component, e.g. a
/// SimulatedLeapMotion; a Leap Motion SDK backend would register its own scheme, and moving to
/// hardware changes this property only).
///
/// Ports: out `measRightPose`, `measLeftPose` (m).
///
/// Events: e_right_hand_lost, e_right_hand_found, e_left_hand_lost, e_left_hand_found.
class LeapMotionDriver : public core::Component {
 public:
  explicit LeapMotionDriver(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  KDL::Frame map(const KDL::Frame& measured) const noexcept;
  void publish(const fieldbus::TrackedHand& tracked, bool& seen, core::OutputPort<KDL::Frame>& port,
               const char* lost, const char* found) noexcept;

  core::Property<std::vector<double>> box_{"interaction_box",
                                           {-0.1175, -0.0735, 0.0825, 0.1175, 0.0735, 0.3175},
                                           "m",
                                           "x_min, y_min, z_min, x_max, y_max, z_max in the device frame"};
  core::Property<KDL::Frame> offset_{"workspace_offset", KDL::Frame::Identity(), "m",
                                     "applied to every measured pose: changes the reference frame"};
  core::Property<double> scale_{"workspace_scale", 1.0, "1", "multiplies measured positions (sensitivity)"};
  core::Property<std::string> device_name_{"device", "", "", "hand tracker backend: sim:<component>"};
  core::OutputPort<KDL::Frame> meas_right_{"measRightPose", "last valid right hand pose", "m"};
  core::OutputPort<KDL::Frame> meas_left_{"measLeftPose", "last valid left hand pose", "m"};

  std::shared_ptr<fieldbus::HandTrackerDevice> device_;
  fieldbus::HandFrame frame_;
  KDL::Vector box_min_, box_max_;
  bool right_seen_ = false, left_seen_ = false;
};

}  // namespace cobra::components
