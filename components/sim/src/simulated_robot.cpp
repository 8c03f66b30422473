#include "cobra/components/sim/simulated_robot.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/kinematics/frame_product.hpp"

namespace cobra::components {
namespace {

std::string count(std::size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); }

/// The property value, or the robot's default when it is empty; refuses a wrong size.
bool perJoint(const std::vector<double>& given, const std::vector<double>& fallback, unsigned joints,
              std::vector<double>& out) {
  out = given.empty() ? fallback : given;
  return out.size() == joints;
}

sim::ForceTorqueSensorModel sensorPreset(const std::string& property, const std::string& name) {
  if (name == "atiNano17") return sim::atiNano17();
  if (name == "atiNano43") return sim::atiNano43();
  if (name == "ftSens") return sim::ftSens();
  throw std::invalid_argument("property " + property + " is '" + name + "'; expected atiNano17, atiNano43 or ftSens");
}

std::string toolDoc(const SimulatedToolDefaults& tool, const char* text) {
  return tool.what.empty() ? std::string(text) : std::string(text) + " (" + tool.what + ")";
}

}  // namespace

SimulatedServoRobotBase::Tool::Tool(const SimulatedToolDefaults& d)
    : tool_frame(d.property_prefix + "tool_frame", KDL::Frame::Identity(), "m",
                 toolDoc(d, "pose of the tool in the frame of the kinematics' tool point")),
      sensor(d.property_prefix + "sensor", d.sensor, "",
             toolDoc(d, "force/torque sensor preset at the tool: atiNano17, atiNano43 or ftSens")),
      sensor_bias(d.property_prefix + "sensor_bias", KDL::Wrench::Zero(), "N, N·m",
                  toolDoc(d, "offset the tool's sensor adds to the true wrench")),
      des_cart_pose("des" + d.port_infix + "CartPose",
                    toolDoc(d, "desired tool pose, world frame; refused (last valid command held; "
                               "e_ik_discontinuity) unless reachable on the current IK branch within max_velocity x "
                               "step length on every joint, or e_ik_failed when out of reach"),
                    "m"),
      contact_wrench("contact" + d.port_infix + "Wrench",
                     toolDoc(d, "simulation only: true wrench on the tool, world orientation, at the tool point"),
                     "N, N·m"),
      meas_cart_pose("meas" + d.port_infix + "CartPose", toolDoc(d, "measured tool pose (encoders), world frame"),
                     "m"),
      meas_wrench("meas" + d.port_infix + "Wrench",
                  toolDoc(d, "force/torque sensor reading, tool frame, at the tool point"), "N, N·m"),
      true_cart_pose("true" + d.port_infix + "CartPose", toolDoc(d, "simulation only: true tool pose, world frame"),
                     "m"),
      held_cart_pose("held" + d.port_infix + "CartPose",
                     toolDoc(d, "in each step refusing a Cartesian command: the pose the tool holds (its last accepted "
                                "command), world frame; the producers of the commands re-sync to it"),
                     "m") {}

SimulatedServoRobotBase::SimulatedServoRobotBase(std::string name, std::string doc, SimulatedRobotDefaults defaults)
    : Component(std::move(name), core::Role::Bridge, std::move(doc)), defaults_(std::move(defaults)) {
  if (defaults_.tools.empty()) throw std::invalid_argument("simulated robot " + defaults_.robot + " has no tool");
  for (const SimulatedToolDefaults& tool : defaults_.tools) tools_.push_back(std::make_unique<Tool>(tool));
  addProperty(base_frame_);
  for (auto& tool : tools_) addProperty(tool->tool_frame);
  addProperty(initial_joints_);
  addProperty(time_constant_);
  addProperty(max_velocity_);
  addProperty(encoder_counts_);
  for (auto& tool : tools_) {
    addProperty(tool->sensor);
    addProperty(tool->sensor_bias);
  }
  addProperty(sensor_cutoff_);
  addProperty(seed_);
  addProperty(speed_scaling_.range(1e-3, 1.0));
  addOperation("lastFailure", std::function<std::string()>([this] { return lastFailure(); }),
               "why the last refused Cartesian command was refused: when, which tool, the pose (m, deg), "
               "out of reach or on another IK branch, and where the robot holds",
               core::ExecutionThread::Client);
  addPort(des_joint_position_);
  addPort(meas_joint_position_);
  for (auto& tool : tools_) {
    addPort(tool->des_cart_pose);
    addPort(tool->contact_wrench);
    addPort(tool->meas_cart_pose);
    addPort(tool->meas_wrench);
    addPort(tool->true_cart_pose);
    addPort(tool->held_cart_pose);
  }
  if (defaults_.twist_ports) {
    addProperty(twist_timeout_);
    addPort(des_twist_);
    addPort(meas_twist_);
  }
  const std::size_t n = tools_.size();
  targets_.resize(n);
  solve_targets_.resize(n);
  fk_.resize(n);
}

SimulatedServoRobotBase::~SimulatedServoRobotBase() = default;

bool SimulatedServoRobotBase::configureHook() {
  robot_.reset();
  for (auto& tool : tools_) tool->sensor_model.reset();
  try {
    kinematics_ = makeKinematics();
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  const auto joints = static_cast<unsigned>(kinematics_->limits().size());
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
  if (!kinematics::validFrame(base_frame_()))
    return refuse("property base_frame must be a finite frame with an orthonormal rotation");
  for (auto& tool : tools_) {
    if (!kinematics::validFrame(tool->tool_frame()))
      return refuse("property " + tool->tool_frame.name() + " must be a finite frame with an orthonormal rotation");
  }
  try {
    sim::ServoRobotModel model{name(), kinematics_->limits(), std::vector<double>(joints, time_constant_()), velocity,
                               counts};
    robot_.emplace(std::move(model), initial_joints_());
    // The default dt (used when two updates share a time stamp): the activity's period, or 1 ms
    // for an activity without one.
    const double period = std::chrono::duration<double>(activity().period()).count();
    default_dt_ = period > 0.0 ? period : 1e-3;
    kinematics_->setContinuity(velocity, default_dt_);
    for (std::size_t i = 0; i < tools_.size(); ++i) {
      Tool& tool = *tools_[i];
      sim::ForceTorqueSensorModel sensor = sensorPreset(tool.sensor.name(), tool.sensor());
      sensor.name = name() + " " + tool.sensor();
      sensor.bias = tool.sensor_bias();
      sensor.filter_cutoff_hz = sensor_cutoff_();
      tool.sensor_model.emplace(std::move(sensor), static_cast<std::uint64_t>(seed_()) + i);
    }
  } catch (const std::invalid_argument& e) {
    robot_.reset();
    for (auto& tool : tools_) tool->sensor_model.reset();
    return refuse(e.what());
  }
  joint_command_.resize(joints);
  solution_.resize(joints);
  meas_joint_position_.setDataSample(KDL::JntArray(joints));
  if (kinematics_->forward(robot_->position(), fk_) != kinematics::IkStatus::Ok)
    return refuse("forward kinematics fails at initial_joints; give a configuration inside the workspace");
  for (std::size_t i = 0; i < tools_.size(); ++i) {
    Tool& tool = *tools_[i];
    tool.commanded = tool.measured = tool.previous = tool.true_pose = tool.fk_true = toWorld(i, fk_[i]);
  }
  measured_fk_.reset(joints);
  true_fk_.reset(joints);
  refusing_ = told_failed_ = told_discontinuity_ = told_not_finite_ = false;
  return true;
}

void SimulatedServoRobotBase::refuseNotFinite() noexcept {
  if (!told_not_finite_) emitEvent("e_command_not_finite");
  told_not_finite_ = true;
}

bool SimulatedServoRobotBase::startHook() {
  last_update_ns_ = -1;
  last_pose_command_ns_ = -1;
  twist_until_ns_ = -1;
  return true;
}

void SimulatedServoRobotBase::cleanupHook() {
  robot_.reset();
  for (auto& tool : tools_) tool->sensor_model.reset();
  kinematics_.reset();
}

KDL::Frame SimulatedServoRobotBase::toWorld(std::size_t tool, const KDL::Frame& fk) const noexcept {
  return kinematics::frameProduct(kinematics::frameProduct(base_frame_(), fk), tools_[tool]->tool_frame());
}

namespace {
/// How many periods a late desired pose may have taken to come, for its continuity bound: a
/// writer late by more is a real-time failure, and a pose jumping after a longer pause is refused.
constexpr double kMaxCommandGap = 4.0;
}  // namespace

double SimulatedServoRobotBase::stepLength() noexcept {
  const std::int64_t now_ns = now().count();
  const double dt = last_update_ns_ < 0 ? std::chrono::duration<double>(activity().period()).count()
                                        : static_cast<double>(now_ns - last_update_ns_) * 1e-9;
  last_update_ns_ = now_ns;
  return dt;
}

void SimulatedServoRobotBase::commandCartesian(double dt) noexcept {
  const KDL::Frame base_inverse = base_frame_().Inverse();
  for (std::size_t i = 0; i < tools_.size(); ++i)
    solve_targets_[i] =
        kinematics::frameProduct(kinematics::frameProduct(base_inverse, targets_[i]), tools_[i]->tool_frame().Inverse());
  // Scaled limits over dt are the full limits over the scaled time.
  kinematics::IkStatus status = kinematics_->solve(solve_targets_, robot_->commanded(), dt * speed_scaling_(), solution_);
  if (status == kinematics::IkStatus::Ok && !robot_->command(solution_)) status = kinematics::IkStatus::BadInput;
  if (status != kinematics::IkStatus::Ok) {
    if (!refusing_) {
      std::size_t moved = 0;
      for (std::size_t i = 0; i < tools_.size(); ++i)
        if (!KDL::Equal(targets_[i], tools_[i]->commanded, 1e-12)) {
          moved = i;
          break;
        }
      refusal_.write({true, std::chrono::duration<double>(now()).count(), status, moved, targets_[moved],
                      tools_[moved]->commanded});
    }
    // One event per reason and refusal episode (until a command is accepted again).
    if (status == kinematics::IkStatus::Discontinuous) {
      if (!told_discontinuity_) emitEvent("e_ik_discontinuity");
      told_discontinuity_ = true;
    } else {
      if (!told_failed_) emitEvent("e_ik_failed");
      told_failed_ = true;
    }
    refusing_ = true;
    // Where the robot holds, for the producers of its commands to re-sync to.
    for (auto& tool : tools_) tool->held_cart_pose.write(tool->commanded);
    return;
  }
  if (refusing_) emitEvent("e_ik_solved");
  refusing_ = told_failed_ = told_discontinuity_ = told_not_finite_ = false;
  for (std::size_t i = 0; i < tools_.size(); ++i) tools_[i]->commanded = targets_[i];
}

namespace {
std::string poseText(const KDL::Frame& f) {
  double r = 0, p = 0, y = 0;
  f.M.GetRPY(r, p, y);
  char text[160];
  std::snprintf(text, sizeof text, "(%.4f, %.4f, %.4f) m, rpy (%.1f, %.1f, %.1f) deg", f.p.x(), f.p.y(), f.p.z(),
                r * 180.0 / M_PI, p * 180.0 / M_PI, y * 180.0 / M_PI);
  return text;
}
}  // namespace

std::string SimulatedServoRobotBase::lastFailure() {
  Refusal refusal;
  {
    const std::lock_guard lock(refusal_reader_);
    refusal_.update();
    refusal = refusal_.front();
  }
  if (!refusal.any) return "no Cartesian command refused";
  std::string why;
  switch (refusal.status) {
    case kinematics::IkStatus::Discontinuous:
      why = "reachable only on another IK branch, or beyond max_velocity in one step (an IK discontinuity)";
      break;
    case kinematics::IkStatus::Unreachable: why = "out of reach (no IK solution)"; break;
    case kinematics::IkStatus::JointLimits: why = "out of reach within the joint limits"; break;
    case kinematics::IkStatus::Singular: why = "at a singular configuration"; break;
    default: why = std::string("refused (") + kinematics::toString(refusal.status) + ")"; break;
  }
  char at[48];
  std::snprintf(at, sizeof at, "at %.3f s ", refusal.t);
  return at + name() + " refused tool " + std::to_string(refusal.tool) + "'s pose " + poseText(refusal.pose) +
         ": " + why + "; it holds " + poseText(refusal.held);
}

void SimulatedServoRobotBase::commandedFromJoints() noexcept {
  if (kinematics_->forward(robot_->commanded(), fk_) != kinematics::IkStatus::Ok) return;
  for (std::size_t i = 0; i < tools_.size(); ++i) tools_[i]->commanded = toWorld(i, fk_[i]);
}

void SimulatedServoRobotBase::updateHook() {
  const double dt = stepLength();
  const std::int64_t now_ns = last_update_ns_;
  bool cartesian = false;
  for (std::size_t i = 0; i < tools_.size(); ++i) {
    Tool& tool = *tools_[i];
    targets_[i] = tool.commanded;
    KDL::Frame pose;
    if (tool.des_cart_pose.read(pose) != core::FlowStatus::NewData) continue;
    if (!kinematics::validFrame(pose)) {
      refuseNotFinite();
      continue;
    }
    targets_[i] = pose;
    cartesian = true;
  }
  if (cartesian) {
    twist_until_ns_ = -1;
    // The continuity bound is max_velocity x the time the command may take: at least one period
    // (a setpoint the servo reaches over its period) and, up to kMaxCommandGap periods, the time
    // since the last desired pose. On the wall clock threads run late: an update early after a
    // late one, or a pose that comes periods after the last (its writer was late), refused a
    // command moving at a feasible speed, and every later one with it (the held command falls
    // behind). On the lockstep clock poses come every period and every step is one: no change.
    const double since = last_pose_command_ns_ < 0 ? dt : static_cast<double>(now_ns - last_pose_command_ns_) * 1e-9;
    last_pose_command_ns_ = now_ns;
    commandCartesian(std::max({dt, default_dt_, std::min(since, kMaxCommandGap * default_dt_)}));
  }
  if (des_joint_position_.read(joint_command_) == core::FlowStatus::NewData) {
    bool finite = true;
    for (unsigned j = 0; j < joint_command_.rows(); ++j) finite = finite && std::isfinite(joint_command_(j));
    if (!finite) {
      refuseNotFinite();
    } else if (robot_->command(joint_command_)) {
      twist_until_ns_ = -1;
      told_not_finite_ = false;
      commandedFromJoints();
    }
  }
  if (defaults_.twist_ports) {
    KDL::Twist twist;
    if (des_twist_.read(twist) == core::FlowStatus::NewData) {
      bool finite = true;
      for (int k = 0; k < 6; ++k) finite = finite && std::isfinite(twist(k));
      if (finite) {
        twist_command_ = twist;
        twist_until_ns_ = now_ns + static_cast<std::int64_t>(twist_timeout_() * 1e9);
      } else {
        refuseNotFinite();
      }
    }
    if (now_ns <= twist_until_ns_ && dt > 0.0) {
      for (std::size_t i = 0; i < tools_.size(); ++i) targets_[i] = tools_[i]->commanded;
      targets_[0] = KDL::addDelta(tools_[0]->commanded, twist_command_, dt);
      commandCartesian(std::max(dt, default_dt_));
    }
  }
  robot_->step(dt);
  publish(dt);
}

void SimulatedServoRobotBase::publish(double dt) noexcept {
  // Forward kinematics only of joints that changed since the last step: a robot at rest (the
  // servo settles exactly on its command, the encoders hold their count) has the same poses.
  if (!measured_fk_.same(robot_->measured())) {
    measured_fk_.ok = kinematics_->forward(robot_->measured(), fk_) == kinematics::IkStatus::Ok;
    if (measured_fk_.ok)
      for (std::size_t i = 0; i < tools_.size(); ++i) tools_[i]->measured = toWorld(i, fk_[i]);
  }
  if (!true_fk_.same(robot_->position())) {
    true_fk_.ok = kinematics_->forward(robot_->position(), fk_) == kinematics::IkStatus::Ok;
    if (true_fk_.ok)
      for (std::size_t i = 0; i < tools_.size(); ++i) tools_[i]->fk_true = toWorld(i, fk_[i]);
  }
  meas_joint_position_.write(robot_->measured());
  for (auto& tool_pointer : tools_) {
    Tool& tool = *tool_pointer;
    if (true_fk_.ok) {
      tool.previous = tool.true_pose;
      tool.true_pose = tool.fk_true;
    }
    tool.meas_cart_pose.write(tool.measured);
    tool.true_cart_pose.write(tool.true_pose);
    KDL::Wrench contact = KDL::Wrench::Zero();
    (void)tool.contact_wrench.read(contact);  // the latest value holds until the simulator writes another
    tool.meas_wrench.write(tool.sensor_model->step(dt, tool.true_pose.M.Inverse() * contact).wrench);
  }
  if (defaults_.twist_ports && dt > 0.0) meas_twist_.write(KDL::diff(tools_[0]->previous, tools_[0]->true_pose, dt));
}

}  // namespace cobra::components
