#pragma once
/// @file
/// WaypointPath: a fixed Cartesian path for one tool, given as a property, sent on request from
/// where the tool is: the simplest Frame Generator (thesis §4.5.5), for tasks whose poses are known
/// when they are written (a scan, a pick-and-place), so that such a task is files only.

#include <kdl/frames.hpp>
#include <string>
#include <vector>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/request.hpp"

namespace cobra::components {

/// Calculation component. Interface:
/// - property `waypoints` (vector, 7 values per pose: x, y, z in m, then the unit quaternion qx,
///   qy, qz, qw of the tool's orientation; in the frame of `measPose`, the robot's base frame;
///   checked at configure: a bad length, a non-finite value or a zero quaternion refuses with the
///   pose's index);
/// - property `relative` (bool, default false): the waypoints are offsets from the measured pose
///   at askPath() instead of poses: each waypoint's position is added to the measured position
///   (base axes, m) and its rotation applied after the measured orientation in base axes (the
///   identity quaternion 0 0 0 1 keeps it). A move relative to wherever the tool is, e.g. a
///   retreat of a few mm along base z whatever the pose the tool stopped at;
/// - in `measPose` (KDL.Frame, m: the tool's measured pose, where every path starts);
/// - out `path` (TGL.MultiAxisPath, one arm, path_type.hpp's encoding: [measured pose, waypoint 1,
///   ..., waypoint n]; the CartesianTrajectoryGenerator's `plannedPath`);
/// - operation `askPath()` (void request, answered in this component's next step: writes `path`
///   and emits `e_path_sent`, or emits `e_no_data` while no measured pose has arrived);
///   `waypointCount()`.
/// Real time: the path is allocated at configure and refilled in place; answering allocates nothing.
class WaypointPath : public core::Component {
 public:
  explicit WaypointPath(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  void askPath();

  core::Property<std::vector<double>> waypoints_{
      "waypoints", {}, "m, 1", "poses of the path after the measured one: x y z [m] qx qy qz qw, 7 values each"};
  core::Property<bool> relative_{"relative", false, "",
                                 "true: each waypoint is an offset from the measured pose (position added, base axes)"};
  core::InputPort<KDL::Frame> meas_pose_{"measPose", "the tool's measured pose: where the path starts", "m"};
  core::OutputPort<trajectory::MultiAxisPath> path_{"path", "[measured pose, waypoints...], 7 values per pose", "m, 1"};

  core::PendingRequest ask_path_;
  trajectory::MultiAxisPath path_data_;
  std::vector<KDL::Frame> offsets_;  // relative: the waypoints as frames, made at configure
  KDL::Frame measured_;
  bool have_measured_ = false;
};

}  // namespace cobra::components
