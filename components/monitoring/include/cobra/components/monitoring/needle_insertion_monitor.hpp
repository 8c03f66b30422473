#pragma once
/// @file
/// Situation awareness for the needle insertion (thesis §4.2): turns the measured wrench
/// and tip pose into the events the puncturing task chart waits for.

#include <cstdint>
#include <kdl/frames.hpp>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/request.hpp"

namespace cobra::components {

/// Decision component: reads pure data, writes only events (edge-triggered, once per crossing).
///
/// Inputs: `measWrench` (KDL::Wrench, N, N·m: the needle robot's sensor reading; the needle axis
/// in its frame is `needle_axis`), `measCartPose` (KDL::Frame, m, world: the needle tip),
/// `targetPose` (KDL::Frame, m, world: the planned tip target). The axial force
/// a = -F·needle_axis is positive when the tissue resists insertion; the extraction force is
/// max(0, -a).
///
/// Events:
///  - `e_skin_touched`: a rises above `contact_force` (N).
///  - `e_skin_penetrated`: after touching, a peak of at least `puncture_min_peak` (N) followed,
///    within `puncture_drop_time` (s), by a drop below (1 - `puncture_drop`)·peak: the membrane
///    rupture. A slow decrease (the robot backing off) is not a puncture.
///  - `e_target_reached`: tip within `target_tolerance` (m) of targetPose's position; re-armed
///    beyond twice the tolerance.
///  - `e_force_over_threshold`: |F| above `max_force` (N); re-armed below 0.8·max_force.
///  - `e_forbidden_region`: the tip within `forbidden_margin` (m) of a capsule of
///    `forbidden_regions` (world frame); re-armed `forbidden_hysteresis` (m) farther out.
///  - `e_needle_trapped`: extraction force above `extraction_threshold` (N);
///    `e_needle_free`: afterwards, extraction force below `release_force` (N).
/// The forbidden-region check uses the measured tip pose and the planned geometry, not the force:
/// a rib or vessel contact cannot be told from a membrane puncture or a fast insertion by the axial
/// force alone, and the geometric check warns before the tip touches (margin).
/// Touched/penetrated are latched for one insertion: the request `reset()` re-arms them in the
/// monitor's next step, before it reads its ports (call it when a new insertion starts; the caller
/// does not wait: core::PendingRequest). updateHook allocates nothing.
class NeedleInsertionMonitor : public core::Component {
 public:
  explicit NeedleInsertionMonitor(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  void reset();
  void checkForce(const KDL::Wrench& wrench, std::int64_t now_ns) noexcept;
  void checkPose(const KDL::Frame& tip) noexcept;

  core::PendingRequest reset_request_;

  core::Property<KDL::Vector> needle_axis_{"needle_axis", KDL::Vector(1, 0, 0), "1",
                                           "needle direction (forwards) in the frame of measWrench, unit vector"};
  core::Property<double> contact_force_{"contact_force", 0.2, "N", "axial force meaning the needle touches the skin"};
  core::Property<double> puncture_min_peak_{"puncture_min_peak", 0.5, "N", "smallest force peak taken as a membrane"};
  core::Property<double> puncture_drop_{"puncture_drop", 0.3, "1", "fraction of the peak the force must lose, (0, 1)"};
  core::Property<double> puncture_drop_time_{"puncture_drop_time", 0.01, "s",
                                             "the drop must happen this soon after the peak"};
  core::Property<double> target_tolerance_{"target_tolerance", 0.002, "m", "tip-to-target distance meaning reached"};
  core::Property<double> max_force_{"max_force", 5.0, "N", "force magnitude above which e_force_over_threshold"};
  core::Property<std::vector<double>> forbidden_regions_{
      "forbidden_regions", {}, "m", "capsules ax, ay, az, bx, by, bz, radius (7 numbers each), world frame"};
  core::Property<double> forbidden_margin_{"forbidden_margin", 0.0, "m", "warn this far outside a forbidden capsule"};
  core::Property<double> forbidden_hysteresis_{"forbidden_hysteresis", 0.0005, "m",
                                               "re-arm distance beyond the margin"};
  core::Property<double> extraction_threshold_{"extraction_threshold", 10.0, "N", "extraction force meaning trapped"};
  core::Property<double> release_force_{"release_force", 2.0, "N",
                                        "extraction force below which a trapped needle is free"};

  core::InputPort<KDL::Wrench> meas_wrench_{"measWrench", "needle force/torque sensor reading", "N, N·m"};
  core::InputPort<KDL::Frame> meas_cart_pose_{"measCartPose", "needle tip pose, world frame", "m"};
  core::InputPort<KDL::Frame> target_pose_{"targetPose", "planned needle tip target, world frame", "m"};

  KDL::Vector axis_;
  bool touched_ = false, penetrated_ = false, over_force_ = false, trapped_ = false;
  bool at_target_ = false, in_forbidden_ = false, have_target_ = false;
  double peak_ = 0.0;
  std::int64_t peak_ns_ = 0;
  KDL::Frame target_;
};

}  // namespace cobra::components
