#include "cobra/components/motion/kinematics_solver_component.hpp"

#include "cobra/kinematics/puma260.hpp"
#include "cobra/kinematics/serial_chain.hpp"
#include "cobra/kinematics/ur5.hpp"

namespace cobra::components {
namespace {

constexpr std::size_t kDhValuesPerJoint = 7;

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
  addPort(joint_positions_);
  addPort(cart_pose_);
  addEventPort(des_cart_pose_);
  addPort(des_joint_positions_);
  addOperation("forward", &KinematicsSolverComponent::forwardOnDemand, this, "tool pose (world frame, m) for joints q");
  addOperation("inverse", &KinematicsSolverComponent::inverseOnDemand, this,
               "joints reaching pose (world frame, m), starting from / nearest to seed");
  addOperation("lastIkStatus", std::function<std::string()>([this] { return std::string(kinematics::toString(last_status_)); }),
               "status of the last inverse kinematics of the data flow: ok, unreachable, joint_limits, ...");
}

KinematicsSolverComponent::~KinematicsSolverComponent() = default;

KdlKinematicsSolver::KdlKinematicsSolver(std::string name) : KinematicsSolverComponent(std::move(name)) {
  setProperty("solver", std::string("kdl_lma"));
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
  q_.resize(joints);
  seed_.resize(joints);
  solution_.resize(joints);
  des_joint_positions_.setDataSample(KDL::JntArray(joints));
  have_seed_ = false;
  failing_ = false;
  return true;
}

void KinematicsSolverComponent::cleanupHook() { kinematics_.reset(); }

void KinematicsSolverComponent::updateHook() {
  if (joint_positions_.read(q_) == core::FlowStatus::NewData && q_.rows() == seed_.rows()) {
    seed_ = q_;
    have_seed_ = true;
    if (kinematics_->forward(q_, pose_) == kinematics::IkStatus::Ok)
      cart_pose_.write(base_frame_() * pose_ * tool_frame_());
  }
  KDL::Frame desired;
  while (des_cart_pose_.read(desired) == core::FlowStatus::NewData) {
    const KDL::Frame target = base_frame_().Inverse() * desired * tool_frame_().Inverse();
    last_status_ = kinematics_->inverse(target, seed_, solution_);
    if (last_status_ == kinematics::IkStatus::Ok) {
      des_joint_positions_.write(solution_);
      if (!have_seed_) seed_ = solution_;  // follow the solution until joints are measured
      if (failing_) emitEvent("e_ik_solved");
      failing_ = false;
    } else if (!failing_) {
      failing_ = true;
      emitEvent("e_ik_failed");
    }
  }
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
