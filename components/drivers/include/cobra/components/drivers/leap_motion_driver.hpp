#pragma once
/// @file
/// The Leap Motion driver (thesis §5.4.4) as a component, on a cobra::fieldbus::HandTrackerDevice
/// found by name.

#include <kdl/frames.hpp>
#include <chrono>
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
/// Each hand's twist is the finite difference of its published poses between two successive
/// frames in which it is seen (over the run time between them, `now()`), low-pass filtered:
/// v ← v + dt/(τ + dt) · (Δpose/dt − v), τ = `twist_filter_time` (s, >= 0; 0: unfiltered). The
/// tracker's 0.5 mm position noise differenced over 5 ms is about 0.14 m/s per axis; τ = 0.05 s
/// (the default) leaves under a tenth of it (a still hand's twist, the driver's test) and lags the
/// hand's velocity by τ. The twist is in the frame of the
/// published poses (after the workspace offset), linear part of the point the pose locates; it is
/// zero while the hand is not seen and for its first frame once found (no previous pose).
///
/// Ports: out `measRightPose`, `measLeftPose` (m); `measRightTwist`, `measLeftTwist` (m/s, rad/s).
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
  /// One hand's published state: the last pose and the filtered twist.
  struct HandState {
    bool seen = false;
    KDL::Frame pose;                        // m: the last published pose
    KDL::Twist twist = KDL::Twist::Zero();  // m/s, rad/s: filtered
    std::chrono::nanoseconds at{0};         // run time of the last published pose
  };
  void publish(const fieldbus::TrackedHand& tracked, HandState& hand, core::OutputPort<KDL::Frame>& pose_port,
               core::OutputPort<KDL::Twist>& twist_port, const char* lost, const char* found) noexcept;

  core::Property<std::vector<double>> box_{"interaction_box",
                                           {-0.1175, -0.0735, 0.0825, 0.1175, 0.0735, 0.3175},
                                           "m",
                                           "x_min, y_min, z_min, x_max, y_max, z_max in the device frame"};
  core::Property<KDL::Frame> offset_{"workspace_offset", KDL::Frame::Identity(), "m",
                                     "applied to every measured pose: changes the reference frame"};
  core::Property<double> scale_{"workspace_scale", 1.0, "1", "multiplies measured positions (sensitivity)"};
  core::Property<std::string> device_name_{"device", "", "", "hand tracker backend: sim:<component>"};
  core::Property<double> twist_filter_time_{"twist_filter_time", 0.05, "s",
                                            "time constant of the low-pass filter on the hands' twists, >= 0"};
  core::OutputPort<KDL::Frame> meas_right_{"measRightPose", "last valid right hand pose", "m"};
  core::OutputPort<KDL::Frame> meas_left_{"measLeftPose", "last valid left hand pose", "m"};
  core::OutputPort<KDL::Twist> twist_right_{"measRightTwist", "right hand twist, filtered; zero while not seen",
                                            "m/s, rad/s"};
  core::OutputPort<KDL::Twist> twist_left_{"measLeftTwist", "left hand twist, filtered; zero while not seen",
                                           "m/s, rad/s"};

  std::shared_ptr<fieldbus::HandTrackerDevice> device_;
  fieldbus::HandFrame frame_;
  KDL::Vector box_min_, box_max_;
  HandState right_, left_;
};

}  // namespace cobra::components
