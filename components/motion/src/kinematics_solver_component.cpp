#include "cobra/components/motion/kinematics_solver_component.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/kinematics/puma260.hpp"
#include "cobra/kinematics/serial_chain.hpp"
#include "cobra/kinematics/ur5.hpp"

namespace cobra::components {
namespace {

constexpr std::size_t kDhValuesPerJoint = 7;
/// rad/s: the UR5's joint speed (thesis §4.3.2 table: 180°/s on every joint).
constexpr double kUr5MaxVelocity = 3.14;

std::vector<kinematics::DhRow> dhRows(const std::vector<double>& table) {
  std::vector<kinematics::DhRow> rows;
  for (std::size_t i = 0; i + kDhValuesPerJoint <= table.size(); i += kDhValuesPerJoint) {
    const double* v = &table[i];
    rows.push_back({v[0], v[1], v[2], v[3], v[4] == 0.0 ? kinematics::JointType::Revolute : kinematics::JointType::Prismatic,
                    v[5], v[6]});
  }
  return rows;
}

}  // namespace

KinematicsSolverComponent::KinematicsSolverComponent(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Kinematics solver (thesis §6.2.4): forward and inverse kinematics, KDL or closed form") {
  addProperty(robot_);
  addProperty(solver_kind_);
  addProperty(dh_table_);
  addProperty(base_frame_);
  addProperty(tool_frame_);
  addProperty(max_joint_velocity_);
  addProperty(period_);
  addProperty(speed_scaling_.range(1e-3, 1.0));
  addPort(joint_positions_);
  addPort(cart_pose_);
  addEventPort(des_cart_pose_);
  addPort(des_joint_positions_);
  addPort(held_cart_pose_);
  addPort(held_joint_positions_);
  addOperation("forward", &KinematicsSolverComponent::forwardOnDemand, this, "tool pose (world frame, m) for joints q");
  addOperation("inverse", &KinematicsSolverComponent::inverseOnDemand, this,
               "joints reaching pose (world frame, m), starting from / nearest to seed");
  addOperation("lastIkStatus", std::function<std::string()>([this] { return std::string(kinematics::toString(last_status_)); }),
               "status of the last inverse kinematics of the data flow: ok, unreachable, joint limits, discontinuous, ...");
}

KinematicsSolverComponent::~KinematicsSolverComponent() = default;

KdlKinematicsSolver::KdlKinematicsSolver(std::string name) : KinematicsSolverComponent(std::move(name)) {
  // Not kdl_lma: KDL's LMA aborts a process that also loads Debian's OMPL (kinematics::kdlLmaConflict).
  setProperty("solver", std::string("kdl_nr"));
}

ClosedFormKinematicsSolver::ClosedFormKinematicsSolver(std::string name) : KinematicsSolverComponent(std::move(name)) {
  setProperty("solver", std::string("closed_form"));
}

kinematics::KinematicsSolver& KinematicsSolverComponent::solver() {
  if (!kinematics_) throw core::Error("component '" + name() + "': configure it first (the solver is made at configure)");
  return *kinematics_;
}

bool KinematicsSolverComponent::configureHook() {
  kinematics::SolverKind kind{};
  try {
    kind = kinematics::parseSolverKind(solver_kind_());
  } catch (const std::exception& e) {
    return refuse(std::string("property solver: ") + e.what());
  }
  if (kind == kinematics::SolverKind::KdlLevenbergMarquardt) {
    if (const std::string conflict = kinematics::kdlLmaConflict(); !conflict.empty())
      return refuse("property solver is 'kdl_lma': " + conflict + "; set solver to kdl_nr or closed_form");
  }
  try {
    // Base and tool frames are applied here, the same way for every robot and solver.
    if (robot_() == "ur5") {
      kinematics_ = kinematics::makeUr5Solver(kind);
    } else if (robot_() == "puma260") {
      kinematics_ = kinematics::makePuma260Solver(kind);
    } else if (robot_() == "dh") {
      if (dh_table_().empty() || dh_table_().size() % kDhValuesPerJoint != 0)
        return refuse("property dh_table has " + std::to_string(dh_table_().size()) +
                      " numbers; give 7 per joint (a, alpha, d, theta, type, lower, upper)");
      if (kind == kinematics::SolverKind::ClosedForm)
        return refuse("robot dh has no closed-form solver; set solver to kdl_nr or kdl_lma");
      kinematics::IterativeIkOptions options;
      options.method = kind == kinematics::SolverKind::KdlNewtonRaphson ? kinematics::IterativeIk::NewtonRaphsonJL
                                                                        : kinematics::IterativeIk::LevenbergMarquardt;
      kinematics_ = std::make_unique<kinematics::SerialChainSolver>(
          kinematics::SerialChainModel(name(), dhRows(dh_table_())), options);
    } else {
      return refuse("property robot is '" + robot_() + "'; expected ur5, puma260 or dh");
    }
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  const unsigned joints = kinematics_->jointCount();
  std::vector<double> velocity = max_joint_velocity_();
  if (velocity.empty()) {
    if (robot_() != "ur5")
      return refuse("property max_joint_velocity is empty: give one velocity limit per joint (rad/s, m/s) for robot " +
                    robot_() + " (only ur5 has a default)");
    velocity.assign(joints, kUr5MaxVelocity);
  }
  if (!(std::isfinite(period_()) && period_() >= 0.0))
    return refuse("property period is " + kinematics::formatNumber(period_()) +
                  " s: give a finite value >= 0 (0: the activity's period)");
  const double period =
      period_() > 0.0 ? period_() : std::chrono::duration<double>(activity().period()).count();
  if (!(period > 0.0))
    return refuse("property period is 0 s and the activity has no period: give the time (s, > 0) a command has to "
                  "be reached in");
  try {
    continuity_ = std::make_unique<kinematics::ContinuousIk>(*kinematics_, velocity, period);
  } catch (const std::invalid_argument& e) {
    return refuse(std::string("property max_joint_velocity: ") + e.what());
  }
  q_.resize(joints);
  measured_.resize(joints);
  solution_.resize(joints);
  candidate_.resize(joints);
  des_joint_positions_.setDataSample(KDL::JntArray(joints));
  have_measured_ = have_solution_ = streaming_ = false;
  refusing_ = told_failed_ = told_discontinuity_ = false;
  return true;
}

void KinematicsSolverComponent::cleanupHook() {
  continuity_.reset();
  kinematics_.reset();
}

void KinematicsSolverComponent::updateHook() {
  if (joint_positions_.read(q_) == core::FlowStatus::NewData && q_.rows() == measured_.rows()) {
    measured_ = q_;
    have_measured_ = true;
    if (kinematics_->forward(q_, pose_) == kinematics::IkStatus::Ok)
      cart_pose_.write(base_frame_() * pose_ * tool_frame_());
  }
  // Held by something else (a drive's quick stop): the next command is judged from there, and
  // the producers of the commands are told.
  KDL::Frame desired;
  if (held_joint_positions_.read(q_) == core::FlowStatus::NewData && q_.rows() == solution_.rows()) {
    solution_ = q_;
    measured_ = q_;
    have_solution_ = have_measured_ = true;
    publishHeld(solution_);
    // The commands of this update were made before their producers knew: not solved.
    while (des_cart_pose_.read(desired) == core::FlowStatus::NewData) {
    }
    streaming_ = false;
    return;
  }
  bool commanded = false;
  while (des_cart_pose_.read(desired) == core::FlowStatus::NewData) {
    const KDL::Frame target = base_frame_().Inverse() * desired * tool_frame_().Inverse();
    // While commands stream in, each is judged from the previous accepted one (the robot's set
    // point: measured joints lag behind it); after a pause, from where the robot is.
    const bool from_solution = have_solution_ && (streaming_ || commanded || !have_measured_);
    if (!from_solution && !have_measured_) {
      last_status_ = kinematics_->inverse(target, solution_, candidate_);  // nothing known yet
    } else {
      // Scaled limits over the period are the full limits over the scaled time.
      last_status_ = continuity_->solve(target, from_solution ? solution_ : measured_,
                                        continuity_->period() * speed_scaling_(), candidate_);
    }
    commanded = true;
    if (last_status_ == kinematics::IkStatus::Ok) {
      solution_ = candidate_;
      have_solution_ = true;
      des_joint_positions_.write(solution_);
      if (refusing_) emitEvent("e_ik_solved");
      refusing_ = told_failed_ = told_discontinuity_ = false;
    } else {
      refusing_ = true;
      if (have_solution_ || have_measured_) publishHeld(from_solution || !have_measured_ ? solution_ : measured_);
      if (last_status_ == kinematics::IkStatus::Discontinuous) {
        if (!told_discontinuity_) emitEvent("e_ik_discontinuity");
        told_discontinuity_ = true;
      } else {
        if (!told_failed_) emitEvent("e_ik_failed");
        told_failed_ = true;
      }
    }
  }
  streaming_ = commanded;
}

void KinematicsSolverComponent::publishHeld(const KDL::JntArray& q) noexcept {
  if (kinematics_->forward(q, pose_) == kinematics::IkStatus::Ok)
    held_cart_pose_.write(base_frame_() * pose_ * tool_frame_());
}

KDL::Frame KinematicsSolverComponent::forwardOnDemand(KDL::JntArray q) {
  KDL::Frame pose;
  const kinematics::IkStatus status = solver().forward(q, pose);
  if (status != kinematics::IkStatus::Ok)
    throw core::Error("forward kinematics of " + std::to_string(q.rows()) + " joint value(s): " +
                      kinematics::toString(status) + " (the robot has " + std::to_string(solver().jointCount()) + " joints)");
  return base_frame_() * pose * tool_frame_();
}

KDL::JntArray KinematicsSolverComponent::inverseOnDemand(KDL::Frame pose, KDL::JntArray seed) {
  KDL::JntArray q(solver().jointCount());
  const kinematics::IkStatus status =
      solver().inverse(base_frame_().Inverse() * pose * tool_frame_().Inverse(), seed, q);
  if (status != kinematics::IkStatus::Ok) throw core::Error(std::string("inverse kinematics: ") + kinematics::toString(status));
  return q;
}

}  // namespace cobra::components
