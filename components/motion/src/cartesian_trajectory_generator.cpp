#include "cobra/components/motion/cartesian_trajectory_generator.hpp"

#include <algorithm>
#include <cmath>

#include "cobra/core/activity.hpp"

namespace cobra::components {
namespace {

constexpr double kPeriodTolerance = 1e-9;  // s

}  // namespace

CartesianTrajectoryGenerator::CartesianTrajectoryGenerator(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Multi-arm Cartesian trajectory generator (thesis §4.5.2): synchronised pose and twist set-points "
                "along a planned path") {
  addProperty(arms_num_.range(1, 16));
  addProperty(max_vel_.range(1e-6, 10.0));
  addProperty(max_ang_vel_.range(1e-6, 100.0));
  addProperty(time_acc_.range(1e-4, 100.0));
  addProperty(stop_time_.range(1e-4, 100.0));
  addProperty(sample_time_.range(1e-6, 10.0));
  addProperty(blend_order_.range(2, 5));
  addProperty(continue_tolerance_.range(0.0, 1.0));
  addProperty(continue_angle_tolerance_.range(0.0, 3.1416));
  addPort(planned_path_);
  addOperation("askGenerateTraj", std::function<void()>([this] { generate_request_.ask(activity()); }),
               "generates the trajectory of the last path received, in this component's next step; answers "
               "e_trajectory_ready, e_traj_failed, e_no_path or e_busy",
               core::ExecutionThread::Client);
  addOperation("askStartMove", std::function<void()>([this] { start_request_.ask(activity()); }),
               "starts writing the set-points of the trajectory in this component's next step; answers e_moving, "
               "e_no_trajectory or e_busy, then e_motion_done",
               core::ExecutionThread::Client);
  addOperation("askStopMove", std::function<void()>([this] { stop_request_.ask(activity()); }),
               "brings every arm to rest in stop_time from the set-point of this component's next step; answers "
               "e_generating_stop then e_motion_stopped, or e_not_moving",
               core::ExecutionThread::Client);
  addOperation("status", std::function<std::string()>([this] { return statusName(); }),
               "the state of Fig. 4.12: NotInitialized, Initialized, WaitPath, PathReady, GeneratingTrajectory, "
               "TrajectoryReady, Moving or GeneratingStop",
               core::ExecutionThread::Client);
  addOperation("lastFailure", std::function<std::string()>([this] { return last_failure_; }),
               "why the last askGenerateTraj failed (empty when it did not)");
}

namespace {

struct StatusText {
  const char* name;   // as status() answers
  const char* event;  // emitted on entering it
};

StatusText textOf(CartesianTrajectoryGenerator::Status status) noexcept {
  using S = CartesianTrajectoryGenerator::Status;
  switch (status) {
    case S::NotInitialized: return {"NotInitialized", "e_not_initialized"};
    case S::Initialized: return {"Initialized", "e_initialized"};
    case S::WaitPath: return {"WaitPath", "e_wait_path"};
    case S::PathReady: return {"PathReady", "e_path_ready"};
    case S::GeneratingTrajectory: return {"GeneratingTrajectory", "e_generating_trajectory"};
    case S::TrajectoryReady: return {"TrajectoryReady", "e_trajectory_ready"};
    case S::Moving: return {"Moving", "e_moving"};
    case S::GeneratingStop: return {"GeneratingStop", "e_generating_stop"};
  }
  return {"?", "e_unknown_state"};
}

}  // namespace

std::string CartesianTrajectoryGenerator::statusName() const { return textOf(status()).name; }

void CartesianTrajectoryGenerator::enter(Status status) noexcept {
  status_.store(status, std::memory_order_release);
  emitEvent(textOf(status).event);
}

bool CartesianTrajectoryGenerator::configureHook() {
  // One pose and one twist output per arm; ports of a previous configuration go (with their
  // connections) when the number of arms changed.
  const auto arms = static_cast<std::size_t>(arms_num_());
  if (pose_ports_.size() != arms) {
    for (auto& port : pose_ports_) removePort(*port);
    for (auto& port : twist_ports_) removePort(*port);
    for (auto& port : held_ports_) removePort(*port);
    pose_ports_.clear();
    twist_ports_.clear();
    held_ports_.clear();
    for (std::size_t i = 1; i <= arms; ++i) {
      pose_ports_.push_back(std::make_unique<core::OutputPort<KDL::Frame>>(
          "desCartPose_" + std::to_string(i), "pose set-point of arm " + std::to_string(i) + " (base frame)", "m"));
      twist_ports_.push_back(std::make_unique<core::OutputPort<KDL::Twist>>(
          "desCartTwist_" + std::to_string(i), "twist set-point of arm " + std::to_string(i) + " (base frame)",
          "m/s, rad/s"));
      held_ports_.push_back(std::make_unique<core::InputPort<KDL::Frame>>(
          "heldPose_" + std::to_string(i),
          "the pose arm " + std::to_string(i) + " is held at (base frame), written by whatever holds it: a sample "
          "ends a motion there and becomes the arm's set-point",
          "m"));
      addPort(*pose_ports_.back());
      addPort(*twist_ports_.back());
      addPort(*held_ports_.back());
    }
  }
  poses_.assign(arms, KDL::Frame::Identity());
  twists_.assign(arms, KDL::Twist::Zero());
  held_now_.assign(arms, 0);
  stops_.clear();
  stops_.reserve(arms);
  trajectory_.reset();
  enter(Status::Initialized);
  return true;
}

void CartesianTrajectoryGenerator::cleanupHook() { enter(Status::NotInitialized); }

bool CartesianTrajectoryGenerator::startHook() {
  const double period = std::chrono::duration<double>(activity().period()).count();
  if (period <= 0.0)
    return refuse("needs a periodic activity: give it a period of sample_time = " + std::to_string(sample_time_()) + " s");
  if (std::abs(period - sample_time_()) > kPeriodTolerance)
    return refuse("sample_time is " + std::to_string(sample_time_()) + " s but the activity period is " +
                  std::to_string(period) + " s; set one to the other");
  trajectory_.reset();
  stops_.clear();
  start_pending_ = false;
  published_ = false;
  resynced_ = false;
  enter(Status::WaitPath);
  return true;
}

void CartesianTrajectoryGenerator::stopHook() { enter(Status::Initialized); }

double CartesianTrajectoryGenerator::elapsed() const {
  return std::chrono::duration<double>(now() - motion_start_).count();
}

void CartesianTrajectoryGenerator::updateHook() {
  resyncToHeldPoses();
  if (status() != Status::Moving && status() != Status::GeneratingStop &&
      planned_path_.readNew(path_) == core::FlowStatus::NewData) {
    trajectory_.reset();  // a new path replaces the old trajectory (Fig. 4.12: back to Path ready)
    enter(Status::PathReady);
  }
  // The requests asked since the last step, in the order a chart asks them.
  if (generate_request_.take()) generate();
  if (start_request_.take()) startMove();
  if (stop_request_.take()) stopMove();
  const Status current = status();
  if (current != Status::Moving && current != Status::GeneratingStop) return;
  if (start_pending_) {
    motion_start_ = now();
    start_pending_ = false;
  }
  const double t = elapsed();
  if (current == Status::Moving) {
    trajectory_->evaluate(t, poses_, twists_);
    publish();
    if (t >= trajectory_->duration()) {
      emitEvent("e_motion_done");
      enter(Status::WaitPath);
    }
  } else {
    evaluateStop(t);
    publish();
    if (t >= stop_time_()) {
      emitEvent("e_motion_stopped");
      enter(Status::WaitPath);
    }
  }
}

void CartesianTrajectoryGenerator::publish() {
  for (std::size_t arm = 0; arm < pose_ports_.size(); ++arm) {
    pose_ports_[arm]->write(poses_[arm]);
    twist_ports_[arm]->write(twists_[arm]);
  }
  published_ = true;
}

void CartesianTrajectoryGenerator::generate() {
  const Status current = status();
  if (current != Status::PathReady && current != Status::TrajectoryReady) {
    emitEvent(current == Status::Moving || current == Status::GeneratingStop ? "e_busy" : "e_no_path");
    return;
  }
  enter(Status::GeneratingTrajectory);
  try {
    const trajectory::CartesianLimits limits{max_vel_(), max_ang_vel_(), time_acc_(), time_acc_()};
    std::vector<std::vector<KDL::Frame>> waypoints = decodeCartesianPath(path_, pose_ports_.size());
    if (published_ && !waypoints.empty()) {
      // waypoints is indexed [waypoint][arm]: each arm's first pose is waypoints[0][arm], set against
      // that arm's own last set-point.
      std::vector<KDL::Frame>& starts = waypoints.front();
      for (std::size_t arm = 0; arm < std::min(starts.size(), poses_.size()); ++arm) {
        const double offset = (starts[arm].p - poses_[arm].p).Norm();
        KDL::Vector axis;
        const double angle = (poses_[arm].M.Inverse() * starts[arm].M).GetRotAngle(axis);
        if (offset <= continue_tolerance_() && angle <= continue_angle_tolerance_()) starts[arm] = poses_[arm];
      }
    }
    trajectory_.emplace(waypoints, limits, blend_order_());
    last_failure_.clear();
    enter(Status::TrajectoryReady);
  } catch (const std::exception& e) {
    last_failure_ = "plannedPath: " + std::string(e.what());
    trajectory_.reset();
    emitEvent("e_traj_failed");
    enter(Status::PathReady);
  }
}

void CartesianTrajectoryGenerator::startMove() {
  if (status() != Status::TrajectoryReady) {
    emitEvent(status() == Status::Moving || status() == Status::GeneratingStop ? "e_busy" : "e_no_trajectory");
    return;
  }
  start_pending_ = true;
  enter(Status::Moving);
}

void CartesianTrajectoryGenerator::stopMove() {
  if (status() != Status::Moving) {
    emitEvent("e_not_moving");
    return;
  }
  if (start_pending_) {  // asked before the first set-point: nothing has moved
    start_pending_ = false;
    emitEvent("e_motion_stopped");
    enter(Status::TrajectoryReady);
    return;
  }
  // Every arm decelerates from the set-point due now (pose, twist, acceleration): this step
  // writes the stop motion's first set-point, that one.
  const double t = elapsed();
  stops_.clear();
  for (std::size_t arm = 0; arm < poses_.size(); ++arm) {
    KDL::Twist acceleration;
    trajectory_->evaluate(t, arm, poses_[arm], twists_[arm], acceleration);
    stops_.emplace_back(poses_[arm], twists_[arm], acceleration, stop_time_());
  }
  motion_start_ = now();
  enter(Status::GeneratingStop);
}

void CartesianTrajectoryGenerator::resyncToHeldPoses() noexcept {
  std::size_t held = 0;
  KDL::Frame pose;
  for (std::size_t arm = 0; arm < held_ports_.size(); ++arm) {
    held_now_[arm] = held_ports_[arm]->read(pose) == core::FlowStatus::NewData;
    if (!held_now_[arm]) continue;
    poses_[arm] = pose;
    ++held;
  }
  const bool resynced_before = resynced_;
  resynced_ = held > 0;
  if (held == 0) return;
  // An arm with no set-point sent since start has none to rest at: only the held arms are written.
  for (std::size_t arm = 0; arm < pose_ports_.size(); ++arm) {
    if (!held_now_[arm] && !published_) continue;
    twists_[arm] = KDL::Twist::Zero();
    pose_ports_[arm]->write(poses_[arm]);
    twist_ports_[arm]->write(twists_[arm]);
  }
  published_ = published_ || held == pose_ports_.size();
  start_pending_ = false;
  const Status current = status();
  // Told once while held step after step (a robot held for long), and whenever a motion ends here.
  if (!resynced_before || current != Status::WaitPath) emitEvent("e_resynced");
  // A stop motion asked for ends here, at rest: its answer is due (a chart may wait for it).
  if (current == Status::GeneratingStop) emitEvent("e_motion_stopped");
  if (current != Status::WaitPath) enter(Status::WaitPath);  // the motion, path and trajectory end here
}

void CartesianTrajectoryGenerator::evaluateStop(double t) {
  for (std::size_t arm = 0; arm < stops_.size(); ++arm) stops_[arm].evaluate(t, poses_[arm], twists_[arm]);
}

}  // namespace cobra::components
