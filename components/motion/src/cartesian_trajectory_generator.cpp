#include "cobra/components/motion/cartesian_trajectory_generator.hpp"

#include <cmath>

#include "cobra/core/activity.hpp"

namespace cobra::components {
namespace {

constexpr std::size_t kAxesPerArm = 4;  // x, y, z (m) and the rotation angle (rad): CartesianTrajectory's axes
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
  addPort(planned_path_);
  addOperation("askGenerateTraj", &CartesianTrajectoryGenerator::askGenerateTraj, this,
               "generates the trajectory of the last path received; answers e_traj_ready, e_traj_failed or e_no_path");
  addOperation("askStartMove", &CartesianTrajectoryGenerator::askStartMove, this,
               "starts writing the set-points of the trajectory; answers e_motion_started or e_no_trajectory, then "
               "e_motion_done");
  addOperation("askStopMove", &CartesianTrajectoryGenerator::askStopMove, this,
               "brings every arm to rest in stop_time; answers e_motion_stopping then e_motion_stopped, or e_not_moving");
  addOperation("status", std::function<std::string()>([this] { return statusName(); }),
               "the state of the generator: WaitPath, PathReady, TrajectoryReady, Moving or Stopping",
               core::ExecutionThread::Client);
  addOperation("lastFailure", std::function<std::string()>([this] { return last_failure_; }),
               "why the last askGenerateTraj failed (empty when it did not)");
}

std::string CartesianTrajectoryGenerator::statusName() const {
  switch (status()) {
    case Status::WaitPath: return "WaitPath";
    case Status::PathReady: return "PathReady";
    case Status::TrajectoryReady: return "TrajectoryReady";
    case Status::Moving: return "Moving";
    case Status::Stopping: return "Stopping";
  }
  return "?";
}

bool CartesianTrajectoryGenerator::configureHook() {
  // One pose and one twist output per arm; ports of a previous configuration go (with their
  // connections) when the number of arms changed.
  const auto arms = static_cast<std::size_t>(arms_num_());
  if (pose_ports_.size() != arms) {
    for (auto& port : pose_ports_) removePort(*port);
    for (auto& port : twist_ports_) removePort(*port);
    pose_ports_.clear();
    twist_ports_.clear();
    for (std::size_t i = 1; i <= arms; ++i) {
      pose_ports_.push_back(std::make_unique<core::OutputPort<KDL::Frame>>(
          "desCartPose_" + std::to_string(i), "pose set-point of arm " + std::to_string(i) + " (base frame)", "m"));
      twist_ports_.push_back(std::make_unique<core::OutputPort<KDL::Twist>>(
          "desCartTwist_" + std::to_string(i), "twist set-point of arm " + std::to_string(i) + " (base frame)",
          "m/s, rad/s"));
      addPort(*pose_ports_.back());
      addPort(*twist_ports_.back());
    }
  }
  poses_.assign(arms, KDL::Frame::Identity());
  twists_.assign(arms, KDL::Twist::Zero());
  stop_orientation_.assign(arms, KDL::Rotation::Identity());
  stop_axis_.assign(arms, KDL::Vector(0, 0, 1));
  stop_states_.assign(arms * kAxesPerArm, trajectory::State{});
  return true;
}

bool CartesianTrajectoryGenerator::startHook() {
  const double period = std::chrono::duration<double>(activity().period()).count();
  if (period <= 0.0)
    return refuse("needs a periodic activity: give it a period of sample_time = " + std::to_string(sample_time_()) + " s");
  if (std::abs(period - sample_time_()) > kPeriodTolerance)
    return refuse("sample_time is " + std::to_string(sample_time_()) + " s but the activity period is " +
                  std::to_string(period) + " s; set one to the other");
  trajectory_.reset();
  stop_.reset();
  start_pending_ = false;
  setStatus(Status::WaitPath);
  return true;
}

void CartesianTrajectoryGenerator::stopHook() {
  if (status() == Status::Moving || status() == Status::Stopping) setStatus(Status::TrajectoryReady);
}

double CartesianTrajectoryGenerator::elapsed() const {
  return std::chrono::duration<double>(now() - motion_start_).count();
}

void CartesianTrajectoryGenerator::updateHook() {
  const Status current = status();
  if (current != Status::Moving && current != Status::Stopping) {
    if (planned_path_.read(path_) == core::FlowStatus::NewData) {
      trajectory_.reset();  // a new path replaces the old trajectory (Fig. 4.12: back to Path ready)
      setStatus(Status::PathReady);
      emitEvent("e_path_ready");
    }
    return;
  }
  if (start_pending_) {
    motion_start_ = now();
    start_pending_ = false;
  }
  const double t = elapsed();
  if (current == Status::Moving) {
    trajectory_->evaluate(t, poses_, twists_);
    publish();
    if (t >= trajectory_->duration()) {
      setStatus(Status::WaitPath);
      emitEvent("e_motion_done");
    }
  } else {
    evaluateStop(t);
    publish();
    if (t >= stop_->duration()) {
      setStatus(Status::WaitPath);
      emitEvent("e_motion_stopped");
    }
  }
}

void CartesianTrajectoryGenerator::publish() {
  for (std::size_t arm = 0; arm < pose_ports_.size(); ++arm) {
    pose_ports_[arm]->write(poses_[arm]);
    twist_ports_[arm]->write(twists_[arm]);
  }
}

void CartesianTrajectoryGenerator::askGenerateTraj() {
  const Status current = status();
  if (current != Status::PathReady && current != Status::TrajectoryReady) {
    emitEvent(current == Status::WaitPath ? "e_no_path" : "e_busy");
    return;
  }
  try {
    const trajectory::CartesianLimits limits{max_vel_(), max_ang_vel_(), time_acc_(), time_acc_()};
    trajectory_.emplace(decodeCartesianPath(path_, pose_ports_.size()), limits, blend_order_());
    last_failure_.clear();
    setStatus(Status::TrajectoryReady);
    emitEvent("e_traj_ready");
  } catch (const std::exception& e) {
    last_failure_ = "plannedPath: " + std::string(e.what());
    trajectory_.reset();
    setStatus(Status::PathReady);
    emitEvent("e_traj_failed");
  }
}

void CartesianTrajectoryGenerator::askStartMove() {
  if (status() != Status::TrajectoryReady) {
    emitEvent(status() == Status::Moving || status() == Status::Stopping ? "e_busy" : "e_no_trajectory");
    return;
  }
  start_pending_ = true;
  setStatus(Status::Moving);
  emitEvent("e_motion_started");
}

void CartesianTrajectoryGenerator::askStopMove() {
  if (status() != Status::Moving) {
    emitEvent("e_not_moving");
    return;
  }
  if (start_pending_) {  // asked before the first set-point: nothing has moved
    start_pending_ = false;
    setStatus(Status::TrajectoryReady);
    emitEvent("e_motion_stopped");
    return;
  }
  // The state of every axis now, from which each decelerates to rest in stop_time.
  const double t = elapsed();
  trajectory_->axes().evaluate(t, stop_states_);
  trajectory_->evaluate(t, poses_, twists_);
  for (std::size_t arm = 0; arm < poses_.size(); ++arm) {
    trajectory::State& angle = stop_states_[kAxesPerArm * arm + 3];
    const double speed = twists_[arm].rot.Norm();
    stop_orientation_[arm] = poses_[arm].M;
    stop_axis_[arm] = speed > 0.0 ? twists_[arm].rot / speed : KDL::Vector(0, 0, 1);
    // The rotation angle axis becomes the angle about the current rotation axis, from 0.
    angle = trajectory::State{0.0, speed, speed > 0.0 ? angle.acceleration : 0.0, 0.0};
  }
  stop_.emplace(trajectory::MultiAxisTrajectory::stop(stop_states_, stop_time_()));
  motion_start_ = now();
  setStatus(Status::Stopping);
  emitEvent("e_motion_stopping");
}

void CartesianTrajectoryGenerator::evaluateStop(double t) {
  stop_->evaluate(t, stop_states_);
  for (std::size_t arm = 0; arm < poses_.size(); ++arm) {
    const trajectory::State* s = &stop_states_[kAxesPerArm * arm];
    poses_[arm].p = KDL::Vector(s[0].position, s[1].position, s[2].position);
    poses_[arm].M = KDL::Rotation::Rot2(stop_axis_[arm], s[3].position) * stop_orientation_[arm];
    twists_[arm].vel = KDL::Vector(s[0].velocity, s[1].velocity, s[2].velocity);
    twists_[arm].rot = stop_axis_[arm] * s[3].velocity;
  }
}

}  // namespace cobra::components
