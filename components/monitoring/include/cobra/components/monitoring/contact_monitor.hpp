#pragma once
/// @file
/// Situation awareness for a tool in compliant contact (thesis §6.4, phases E-G): contact made and
/// lost, the tool pushed off its nominal path and back on it, and a contact force above its limit,
/// as events, from the measured wrench and the measured and nominal tool poses.

#include <cstdint>
#include <kdl/frames.hpp>
#include <string>

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Decision component. Inputs: `measWrench` (N, N·m: the measured external wrench at the tool
/// point, e.g. an EquivalentWrench's output; only its force is used), `measPose` (m: the tool's
/// measured pose) and `nominalPose` (m: where the task wants the tool, e.g. a trajectory
/// generator's set-point; same frame as measPose).
/// Events, edge-triggered with hysteresis (each once per crossing):
/// - `e_contact` when |force| rises above `contact_force` (N); `e_contact_lost` when it stays
///   below `release_force` (N, <= contact_force) for `release_time` (s; a dip shorter than that,
///   e.g. the tool bouncing on a stiff surface, is not a loss);
/// - `e_force_over_limit` when |force| rises above `max_force` (N, > contact_force); re-armed once
///   it is below `release_force`;
/// - `e_off_path` when the distance between the measured and the nominal position rises above
///   `off_path_distance` (m); `e_on_path` when it falls below `on_path_distance` (m, <
///   off_path_distance) after that. No distance before both poses have arrived.
/// updateHook allocates nothing.
class ContactMonitor : public core::Component {
 public:
  explicit ContactMonitor(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  void watchForce(double force);
  void watchPath(double distance);

  core::Property<double> contact_force_{"contact_force", 1.0, "N", "force magnitude meaning contact, > 0"};
  core::Property<double> release_force_{"release_force", 0.5, "N",
                                        "force magnitude meaning no contact, 0 <= release_force <= contact_force"};
  core::Property<double> release_time_{"release_time", 0.05, "s",
                                       "how long the force must stay below release_force to lose contact, >= 0"};
  core::Property<double> max_force_{"max_force", 10.0, "N", "contact force limit, > contact_force"};
  core::Property<double> off_path_{"off_path_distance", 0.005, "m",
                                   "measured-to-nominal distance meaning the tool is off its path, > 0"};
  core::Property<double> on_path_{"on_path_distance", 0.001, "m",
                                  "distance meaning the tool is back on its path, 0 < on_path < off_path"};

  core::InputPort<KDL::Wrench> wrench_{"measWrench", "measured external wrench at the tool point", "N, N·m"};
  core::InputPort<KDL::Frame> meas_pose_{"measPose", "the tool's measured pose", "m"};
  core::InputPort<KDL::Frame> nominal_pose_{"nominalPose", "the tool's nominal pose (same frame as measPose)", "m"};

  KDL::Frame measured_, nominal_;
  bool have_measured_ = false, have_nominal_ = false;
  bool in_contact_ = false, over_limit_ = false, off_path_state_ = false;
  std::int64_t below_since_ns_ = -1;  // since when the force is below release_force in contact (-1: it is not)
};

}  // namespace cobra::components
