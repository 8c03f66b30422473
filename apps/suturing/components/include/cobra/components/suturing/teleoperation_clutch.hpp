#pragma once
/// @file
/// The haptic device's engagement (thesis §5.5: InitHapticDevice, "the haptic devices are
/// initialized and enabled"): from the moment the teleoperation starts, the tool follows the
/// device's motion from where each of them was, so that taking over moves nothing by itself.

#include <string>

#include <kdl/frames.hpp>

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Calculation component, one per arm. Frames: world, m, rad.
///
/// Interface:
/// - property `scale` (1, > 0: tool metres per device metre);
/// - inputs `masterPose` (KDL.Frame: the device's pose, its stylus or hand, as its driver
///   publishes it), `slavePose` (KDL.Frame: the tool's measured pose);
/// - output `desPose` (KDL.Frame: the tool's set-point): with M0 and S0 the first master and slave
///   samples after start (the engagement), and M the newest master sample, position
///   S0.p + scale·(M.p - M0.p), orientation (M.M·M0.M⁻¹)·S0.M (the device's rotation since the
///   engagement, in world axes). Nothing is written before both inputs have data; a new start
///   engages again.
/// Real time: updateHook reads, composes two frames and writes; it allocates nothing.
class TeleoperationClutch : public core::Component {
 public:
  explicit TeleoperationClutch(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  core::Property<double> scale_{"scale", 1.0, "1", "tool metres per device metre, > 0"};
  core::InputPort<KDL::Frame> master_{"masterPose", "the haptic device's pose", "m"};
  core::InputPort<KDL::Frame> slave_{"slavePose", "the tool's measured pose", "m"};
  core::OutputPort<KDL::Frame> des_{"desPose", "the tool's set-point: the device's motion since the engagement", "m"};

  bool engaged_ = false, have_slave_ = false;
  KDL::Frame master0_, slave0_, slave_now_;
};

}  // namespace cobra::components
