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
/// - properties `scale` (1, > 0: tool metres per device metre), `engagement_time` (s, >= 0:
///   M0's position is the mean of the device samples that arrive in that time from the first,
///   so that a noisy tracker's one sample does not offset the whole teleoperation; 0: the first
///   sample; M0's orientation is the last sample's), `smoothing_time`
///   (s, >= 0; 0: none: the time constant of a first-order filter on the device's positions
///   after the engagement, stepped at each new sample by the time since the previous one: a
///   noisy tracker's jitter would shake the tool);
/// - inputs `masterPose` (KDL.Frame: the device's pose, its stylus or hand, as its driver
///   publishes it), `slavePose` (KDL.Frame: the tool's measured pose);
/// - output `desPose` (KDL.Frame: the tool's set-point): with M0 and S0 the first master and slave
///   samples after start (the engagement), and M the newest master sample, position
///   S0.p + scale·(M̃.p - M0.p) (M̃: M's position filtered by smoothing_time), orientation (M.M·M0.M⁻¹)·S0.M (the device's rotation since the
///   engagement, in world axes; S0 is the tool's pose when the first engagement sample came).
///   Nothing is written before slavePose has data; until the device's first sample (a device
///   behind a delayed link), desPose is the tool's measured pose, so that a coupling reading it
///   sees no master-slave offset; while the first samples are averaged, it is S0 (the coupling
///   holds the tool there); a new start engages again.
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
  core::Property<double> engagement_time_{"engagement_time", 0.0, "s",
                                          "device samples averaged into the engagement position over it, >= 0"};
  core::Property<double> smoothing_time_{"smoothing_time", 0.0, "s",
                                         "time constant of the filter on the device's positions, >= 0 (0: none)"};
  core::InputPort<KDL::Frame> master_{"masterPose", "the haptic device's pose", "m"};
  core::InputPort<KDL::Frame> slave_{"slavePose", "the tool's measured pose", "m"};
  core::OutputPort<KDL::Frame> des_{"desPose", "the tool's set-point: the device's motion since the engagement", "m"};

  bool engaged_ = false, have_slave_ = false;
  int averaged_ = 0;
  KDL::Vector master_sum_ = KDL::Vector::Zero();  // m
  KDL::Vector smoothed_ = KDL::Vector::Zero();    // m: the filtered device position
  std::chrono::nanoseconds last_sample_{0}, first_sample_{0};
  KDL::Frame master0_, slave0_, slave_now_;
};

}  // namespace cobra::components
