#include "cobra/components/sim/simulated_robot.hpp"

#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/ur5.hpp"

namespace cobra::components {
namespace {

std::string count(std::size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); }

/// The property value, or the robot's default when it is empty; refuses a wrong size.
bool perJoint(const std::vector<double>& given, const std::vector<double>& fallback, unsigned joints,
              std::vector<double>& out) {
  out = given.empty() ? fallback : given;
  return out.size() == joints;
}

sim::ForceTorqueSensorModel sensorPreset(const std::string& name) {
  if (name == "atiNano17") return sim::atiNano17();
  if (name == "atiNano43") return sim::atiNano43();
  if (name == "ftSens") return sim::ftSens();
  throw std::invalid_argument("property sensor is '" + name + "'; expected atiNano17, atiNano43 or ftSens");
}

}  // namespace

SimulatedServoRobotBase::SimulatedServoRobotBase(std::string name, std::string doc, SimulatedRobotDefaults defaults)
    : Component(std::move(name), core::Role::Bridge, std::move(doc)), defaults_(std::move(defaults)) {
  addProperty(base_frame_);
  addProperty(tool_frame_);
  addProperty(initial_joints_);
  addProperty(time_constant_);
  addProperty(max_velocity_);
  addProperty(encoder_counts_);
  addProperty(sensor_);
  addProperty(sensor_bias_);
  addProperty(sensor_cutoff_);
  addProperty(seed_);
  addPort(des_cart_pose_);
  addPort(des_joint_position_);
  addPort(contact_wrench_);
  addPort(meas_cart_pose_);
  addPort(meas_joint_position_);
  addPort(meas_wrench_);
  addPort(true_cart_pose_);
  if (defaults_.twist_ports) {
    addProperty(twist_timeout_);
    addPort(des_twist_);
    addPort(meas_twist_);
  }
}

SimulatedServoRobotBase::~SimulatedServoRobotBase() = default;

bool SimulatedServoRobotBase::configureHook() {
  servo_.reset();
  robot_.reset();
  sensor_model_.reset();
  try {
    solver_ = makeSolver();
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  const unsigned joints = solver_->jointCount();
  const std::string robot = defaults_.robot;
  if (initial_joints_().size() != joints)
    return refuse("property initial_joints has " + count(initial_joints_().size(), "value") + "; the " + robot +
                  " has " + count(joints, "joint") + ": give one position per joint (rad, m for prismatic joints)");
  std::vector<double> velocity, counts;
  if (!perJoint(max_velocity_(), defaults_.max_velocity, joints, velocity))
    return refuse("property max_velocity has " + count(max_velocity_().size(), "value") + "; the " + robot + " has " +
                  count(joints, "joint") + ": give one limit per joint (rad/s, m/s) or none for the defaults");
  if (!perJoint(encoder_counts_(), defaults_.encoder_counts, joints, counts))
    return refuse("property encoder_counts has " + count(encoder_counts_().size(), "value") + "; the " + robot +
                  " has " + count(joints, "joint") + ": give one value per joint or none for the defaults");
  if (!std::isfinite(time_constant_()) || time_constant_() <= 0.0)
    return refuse("property time_constant is " + std::to_string(time_constant_()) + " s; expected > 0 s");
  if (defaults_.twist_ports && !(twist_timeout_() > 0.0))
    return refuse("property twist_timeout is " + std::to_string(twist_timeout_()) + " s; expected > 0 s");
  if (!kinematics::validFrame(base_frame_()) || !kinematics::validFrame(tool_frame_()))
    return refuse("properties base_frame and tool_frame must be finite frames with an orthonormal rotation");
  try {
    sim::ServoRobotModel model{name(), solver_->limits(), std::vector<double>(joints, time_constant_()), velocity,
                               counts};
    robot_.emplace(std::move(model), initial_joints_());
    // The servo's default dt (used when two updates share a time stamp): the activity's period,
    // or 1 ms for an activity without one.
    const double period = std::chrono::duration<double>(activity().period()).count();
    servo_.emplace(*solver_, *robot_, period > 0.0 ? period : 1e-3);
    sim::ForceTorqueSensorModel sensor = sensorPreset(sensor_());
    sensor.name = name() + " " + sensor_();
    sensor.bias = sensor_bias_();
    sensor.filter_cutoff_hz = sensor_cutoff_();
    sensor_model_.emplace(std::move(sensor), static_cast<std::uint64_t>(seed_()));
  } catch (const std::invalid_argument& e) {
    servo_.reset();
    robot_.reset();
    return refuse(e.what());
  }
  joint_command_.resize(joints);
  meas_joint_position_.setDataSample(KDL::JntArray(joints));
  KDL::Frame fk;
  if (solver_->forward(robot_->position(), fk) != kinematics::IkStatus::Ok)
    return refuse("forward kinematics fails at initial_joints; give a configuration inside the workspace");
  commanded_pose_ = measured_pose_ = previous_pose_ = true_pose_ = base_frame_() * fk * tool_frame_();
  measured_fk_.reset(joints);
  true_fk_.reset(joints);
  refusing_ = told_failed_ = told_discontinuity_ = false;
  return true;
}

bool SimulatedServoRobotBase::startHook() {
  last_update_ns_ = -1;
  twist_until_ns_ = -1;
  return true;
}

void SimulatedServoRobotBase::cleanupHook() {
  servo_.reset();
  robot_.reset();
  sensor_model_.reset();
  solver_.reset();
}

double SimulatedServoRobotBase::stepLength() noexcept {
  const std::int64_t now_ns = now().count();
  const double dt = last_update_ns_ < 0 ? std::chrono::duration<double>(activity().period()).count()
                                        : static_cast<double>(now_ns - last_update_ns_) * 1e-9;
  last_update_ns_ = now_ns;
  return dt;
}

void SimulatedServoRobotBase::commandCartesian(const KDL::Frame& world_target, double dt) noexcept {
  const KDL::Frame target = base_frame_().Inverse() * world_target * tool_frame_().Inverse();
  const sim::CartesianCommandStatus status = dt > 0.0 ? servo_->command(target, dt) : servo_->command(target);
  if (status.holding) {
    // One event per reason and refusal episode (until a command is accepted again).
    if (status.ik == kinematics::IkStatus::Discontinuous) {
      if (!told_discontinuity_) emitEvent("e_ik_discontinuity");
      told_discontinuity_ = true;
    } else {
      if (!told_failed_) emitEvent("e_ik_failed");
      told_failed_ = true;
    }
    refusing_ = true;
    return;
  }
  if (refusing_) emitEvent("e_ik_solved");
  refusing_ = told_failed_ = told_discontinuity_ = false;
  commanded_pose_ = world_target;
}

void SimulatedServoRobotBase::updateHook() {
  const double dt = stepLength();
  const std::int64_t now_ns = last_update_ns_;
  KDL::Frame pose;
  if (des_cart_pose_.read(pose) == core::FlowStatus::NewData && kinematics::validFrame(pose)) {
    twist_until_ns_ = -1;
    commandCartesian(pose, dt);
  }
  if (des_joint_position_.read(joint_command_) == core::FlowStatus::NewData && robot_->command(joint_command_)) {
    twist_until_ns_ = -1;
    KDL::Frame fk;
    if (solver_->forward(robot_->commanded(), fk) == kinematics::IkStatus::Ok)
      commanded_pose_ = base_frame_() * fk * tool_frame_();
  }
  if (defaults_.twist_ports) {
    if (des_twist_.read(twist_command_) == core::FlowStatus::NewData)
      twist_until_ns_ = now_ns + static_cast<std::int64_t>(twist_timeout_() * 1e9);
    if (now_ns <= twist_until_ns_ && dt > 0.0) commandCartesian(KDL::addDelta(commanded_pose_, twist_command_, dt), dt);
  }
  robot_->step(dt);
  publish(dt);
}

void SimulatedServoRobotBase::publish(double dt) noexcept {
  // Forward kinematics only of joints that changed since the last step: a robot at rest (the
  // servo settles exactly on its command, the encoders hold their count) has the same poses.
  KDL::Frame fk;
  if (!measured_fk_.same(robot_->measured())) {
    measured_fk_.ok = solver_->forward(robot_->measured(), fk) == kinematics::IkStatus::Ok;
    if (measured_fk_.ok) measured_pose_ = base_frame_() * fk * tool_frame_();
  }
  if (!true_fk_.same(robot_->position())) {
    true_fk_.ok = solver_->forward(robot_->position(), fk) == kinematics::IkStatus::Ok;
    if (true_fk_.ok) fk_true_pose_ = base_frame_() * fk * tool_frame_();
  }
  if (true_fk_.ok) {
    previous_pose_ = true_pose_;
    true_pose_ = fk_true_pose_;
  }
  meas_joint_position_.write(robot_->measured());
  meas_cart_pose_.write(measured_pose_);
  true_cart_pose_.write(true_pose_);
  if (defaults_.twist_ports && dt > 0.0) meas_twist_.write(KDL::diff(previous_pose_, true_pose_, dt));
  KDL::Wrench contact = KDL::Wrench::Zero();
  (void)contact_wrench_.read(contact);  // the latest value holds until the simulator writes another
  meas_wrench_.write(sensor_model_->step(dt, true_pose_.M.Inverse() * contact).wrench);
}

SimulatedISURRobot::SimulatedISURRobot(std::string name)
    : SimulatedServoRobotBase(
          std::move(name),
          "Simulated I-SUR puncturing robot (thesis §4.5.7 interface): stiff servo, IK, ATI Nano17 at the needle",
          SimulatedRobotDefaults{.robot = "I-SUR",
                                 .initial_joints = {0.1, 0.1, 0.1, 0.0, 0.0, 0.6, 0.6, 0.0},
                                 .max_velocity = {0.1, 0.1, 0.1, 1.5, 1.5, 1.5, 1.5, 1.5},
                                 .encoder_counts = {1e6, 1e6, 1e6, 262144, 262144, 262144, 262144, 262144},
                                 .sensor = "atiNano17",
                                 .twist_ports = false}) {}

std::unique_ptr<kinematics::KinematicsSolver> SimulatedISURRobot::makeSolver() const {
  return std::make_unique<kinematics::IsurPuncturingSolver>();
}

SimulatedUR5Robot::SimulatedUR5Robot(std::string name)
    : SimulatedServoRobotBase(
          std::move(name),
          "Simulated UR5 (thesis §4.5.8 interface): stiff servo, closed-form IK, twist commands, ATI Nano43",
          SimulatedRobotDefaults{.robot = "UR5",
                                 .initial_joints = {0.0, -1.57, 1.57, -1.57, -1.57, 0.0},
                                 .max_velocity = std::vector<double>(6, 3.14),
                                 .encoder_counts = std::vector<double>(6, 262144),
                                 .sensor = "atiNano43",
                                 .twist_ports = true}) {}

std::unique_ptr<kinematics::KinematicsSolver> SimulatedUR5Robot::makeSolver() const {
  return std::make_unique<kinematics::Ur5Solver>();
}

}  // namespace cobra::components
