#pragma once
/// @file
/// The thesis' Multi-Arm Cartesian Trajectory Generator (§4.5.2, Fig. 4.12): a Calculation
/// component around TGL's CartesianTrajectory that turns a planned path into synchronised pose and
/// twist set-points for `arms_num` arms.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/request.hpp"
#include "cobra/trajectory/cartesian.hpp"
#include "cobra/trajectory/cartesian_stop.hpp"

namespace cobra::components {

/// Interface (thesis names):
/// - properties `arms_num` (1..16), `max_vel` (m/s, per Cartesian position axis), `max_ang_vel`
///   (rad/s), `time_acc` (s, blend duration), `stop_time` (s), `sample_time` (s: the activity
///   period it expects; start refuses another period), `blend_order` (2..5);
/// - operations `askGenerateTraj()`, `askStartMove()`, `askStopMove()` (void requests, answered by
///   events), `status()` (the state of Fig. 4.12, e.g. "WaitPath") and `lastFailure()`;
/// - ports `plannedPath` (in, TGL.MultiAxisPath, encoded as path_type.hpp says),
///   `desCartPose_i` / `desCartTwist_i` (out, i = 1..arms_num, made at configure), `heldPose_i`
///   (in, made at configure: see Re-sync) and `events`.
///
/// States, exactly those of Fig. 4.12, each entered with an event on `events`:
/// NotInitialized (e_not_initialized: created, or cleaned up) -> configure -> Initialized
/// (e_initialized) -> start -> WaitPath (e_wait_path) -> a path arrives -> PathReady
/// (e_path_ready) -> askGenerateTraj -> GeneratingTrajectory (e_generating_trajectory) ->
/// TrajectoryReady (e_trajectory_ready), or back to PathReady after e_traj_failed (reason in
/// lastFailure()) -> askStartMove -> Moving (e_moving) -> at the end e_motion_done -> WaitPath;
/// Moving -> askStopMove -> GeneratingStop (e_generating_stop: the stop motion runs) -> at rest
/// e_motion_stopped -> WaitPath. stop returns to Initialized. A request in the wrong state answers
/// e_no_path, e_no_trajectory, e_not_moving or e_busy and changes nothing. The three requests only
/// mark themselves (from any thread, without waiting: core::PendingRequest) and are answered in
/// this component's next step, in the order generate, start, stop: the supervisor asking spends
/// nothing on them.
///
/// Continuity of the command: a path's first waypoint is normally the arm's measured pose, which
/// differs from the set-point the robot was last sent by its tracking error and, under the
/// variable admittance, by the compliance displacement. Starting there would step the command (and
/// a robot's continuity rule refuses steps it cannot make in one period). So when the first
/// waypoint lies within `continue_tolerance` (m) and `continue_angle_tolerance` (rad) of the
/// arm's last set-point since start, the trajectory starts from that set-point instead; farther
/// away (another component moved the arm meanwhile) the waypoint is kept.
///
/// Re-sync (ARCHITECTURE §7, "Continuity in the control path"): `heldPose_i` (in, i = 1..arms_num,
/// KDL.Frame, base frame, m) is written by whatever holds arm i's robot (the robot bridge or
/// kinematics solver refusing a command, a state validator, a drive's quick stop), or by the
/// variable admittance between this component and the robot (its heldRefPose: the reference its
/// re-synced output steps about), in each step the arm is held. On such a sample, in any running
/// state, the arm's set-point becomes that pose, every arm's twist zero, and the set-points are
/// written in that step; e_resynced is emitted (once while held step after step, unless a motion
/// ends). A motion (Moving, GeneratingStop, or a start asked for) ends there: every arm is at
/// rest at once, the held arms at their held pose and the others
/// at their set-point (a stop in one step: no jump in pose, a step in velocity), and the state
/// goes to WaitPath with e_wait_path (after e_motion_stopped when a stop motion was running: the
/// answer askStopMove promised); the old path and trajectory are dropped (PathReady and
/// TrajectoryReady also go to WaitPath), since they began where the arm no longer is. No motion
/// resumes by itself: a new path (a re-plan: the chart's recovery) is needed, and it starts from the
/// held pose by the continuity rule above. askStopMove after it answers e_not_moving.
///
/// Real time: while Moving or GeneratingStop, updateHook evaluates and writes without allocating. A new
/// path is copied when it is read, and a trajectory generated when asked (once per path, while not
/// moving: no set-point is due then; both allocate).
/// The stop motion is TGL's CartesianStop per arm: from the pose, twist and acceleration of the
/// set-point being sent to rest in `stop_time`, on SO(3), continuous up to acceleration.
class CartesianTrajectoryGenerator : public core::Component {
 public:
  enum class Status {
    NotInitialized,
    Initialized,
    WaitPath,
    PathReady,
    GeneratingTrajectory,
    TrajectoryReady,
    Moving,
    GeneratingStop,
  };

  explicit CartesianTrajectoryGenerator(std::string name);

  Status status() const { return status_.load(std::memory_order_acquire); }
  /// The trajectory being followed (nullptr before askGenerateTraj succeeds). Read it when the
  /// component is not Running, or from its own thread.
  const trajectory::CartesianTrajectory* trajectory() const { return trajectory_ ? &*trajectory_ : nullptr; }

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;
  void cleanupHook() override;

 private:
  // The requests askGenerateTraj, askStartMove and askStopMove, answered in updateHook.
  void generate();
  void startMove();
  void stopMove();
  std::string statusName() const;
  /// Enters `status` and emits its event (real-time safe).
  void enter(Status status) noexcept;
  double elapsed() const;
  /// Writes the set-points in poses_/twists_ on every arm's ports.
  void publish();
  /// Fills poses_/twists_ with the stop motion at `t` s after it began.
  void evaluateStop(double t);
  /// Reads every arm's held pose; on a new one re-syncs (see the class comment). Real-time safe.
  void resyncToHeldPoses() noexcept;

  core::Property<int> arms_num_{"arms_num", 1, "1", "number of arms (pose and twist output pairs)"};
  core::Property<double> max_vel_{"max_vel", 0.05, "m/s", "maximum velocity of each Cartesian position axis"};
  core::Property<double> max_ang_vel_{"max_ang_vel", 0.5, "rad/s", "maximum angular velocity of each arm"};
  core::Property<double> time_acc_{"time_acc", 0.2, "s", "acceleration time of each axis (blend duration)"};
  core::Property<double> stop_time_{"stop_time", 0.2, "s", "time in which askStopMove brings every arm to rest"};
  core::Property<double> sample_time_{"sample_time", 0.001, "s", "period of the set-points: the activity period"};
  core::Property<int> blend_order_{"blend_order", 5, "1", "order of the polynomial blends (2..5)"};
  core::Property<double> continue_tolerance_{
      "continue_tolerance", 0.002, "m",
      "a path whose first waypoint is this close to the arm's last set-point starts from that set-point"};
  core::Property<double> continue_angle_tolerance_{
      "continue_angle_tolerance", 0.02, "rad",
      "the same for the orientation: angle between the first waypoint and the last set-point"};

  core::InputPort<trajectory::MultiAxisPath> planned_path_{"plannedPath", "path to follow, 7 values per arm per waypoint (x y z m, qx qy qz qw)", "m"};
  std::vector<std::unique_ptr<core::OutputPort<KDL::Frame>>> pose_ports_;
  std::vector<std::unique_ptr<core::OutputPort<KDL::Twist>>> twist_ports_;
  std::vector<std::unique_ptr<core::InputPort<KDL::Frame>>> held_ports_;

  std::atomic<Status> status_{Status::NotInitialized};
  std::string last_failure_;
  trajectory::MultiAxisPath path_;
  std::optional<trajectory::CartesianTrajectory> trajectory_;
  std::chrono::nanoseconds motion_start_{0};
  bool start_pending_ = false;  // askStartMove was called: the next update stamps the start
  core::PendingRequest generate_request_, start_request_, stop_request_;

  std::vector<trajectory::CartesianStop> stops_;  // one per arm while GeneratingStop (capacity reserved)

  std::vector<KDL::Frame> poses_;   // workspace: one per arm; the last set-points once published
  bool published_ = false;          // poses_ hold set-points sent since the last start
  std::vector<KDL::Twist> twists_;  // workspace: one per arm
  std::vector<unsigned char> held_now_;  // workspace: arm i brought a held pose in this step
  bool resynced_ = false;                // the last step re-synced (e_resynced told once while held)
};

}  // namespace cobra::components
