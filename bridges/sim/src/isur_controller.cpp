#include "cobra/bridges/sim/isur_controller.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/bridges/isur_udp_server.hpp"

namespace cobra::bridges {

namespace {

const IsurSimControllerOptions& checked(const IsurSimControllerOptions& o) {
  const std::string who = "I-SUR simulated controller: ";
  if (!(o.period > 0.0 && o.period <= 0.1))
    throw std::runtime_error(who + "period is " + std::to_string(o.period) + " s: give (0, 0.1]");
  if (o.tools < 1 || o.tools > isur::kMaxTools)
    throw std::runtime_error(who + "tools is " + std::to_string(o.tools) + ": give 1 (puncturing) or 2 (suturing)");
  if (!(o.actuation_time > 0.0 && std::isfinite(o.actuation_time)))
    throw std::runtime_error(who + "actuation_time is " + std::to_string(o.actuation_time) + " s: give > 0");
  return o;
}

std::vector<double> initialJoints(const IsurSimControllerOptions& o, const kinematics::JointLimits& limits) {
  if (!o.initial_joints.empty()) {
    if (o.initial_joints.size() != limits.lower.size())
      throw std::runtime_error("I-SUR simulated controller: initial_joints has " +
                               std::to_string(o.initial_joints.size()) + " values: give " +
                               std::to_string(limits.lower.size()) + " (rad / m)");
    return o.initial_joints;
  }
  std::vector<double> q(limits.lower.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = 0.5 * (limits.lower[i] + limits.upper[i]);
  return q;
}

void toPose(const KDL::Frame& frame, isur::Pose& pose) {
  for (int i = 0; i < 3; ++i) pose.position[static_cast<std::size_t>(i)] = frame.p(i);
  frame.M.GetQuaternion(pose.quaternion[0], pose.quaternion[1], pose.quaternion[2], pose.quaternion[3]);
}

KDL::Frame toFrame(const isur::Pose& pose) {
  return KDL::Frame(KDL::Rotation::Quaternion(pose.quaternion[0], pose.quaternion[1], pose.quaternion[2],
                                              pose.quaternion[3]),
                    KDL::Vector(pose.position[0], pose.position[1], pose.position[2]));
}

}  // namespace

IsurSimController::IsurSimController(IsurSimControllerOptions options)
    : options_(checked(options)),
      socket_(options_.bind_host, options_.bind_port),
      server_(resolve(options_.server_host, options_.server_port)),
      server_known_(options_.server_port != 0),
      external_(options_.tools, KDL::Wrench::Zero()) {
  const kinematics::JointLimits* limits = nullptr;
  if (options_.tools == 1) {
    puncturing_ = std::make_unique<kinematics::IsurPuncturingSolver>();
    limits = &puncturing_->limits();
    sensors_.emplace_back(sim::atiNano17(), options_.seed);
  } else {
    suturing_ = std::make_unique<kinematics::IsurSuturingSolver>();
    limits = &suturing_->limits();
    sensors_.emplace_back(sim::atiNano43(), options_.seed);  // the Endo Stitch arm (§5.3.2)
    sensors_.emplace_back(sim::atiNano17(), options_.seed + 1);
  }
  robot_ = std::make_unique<sim::ServoRobot>(
      sim::uniformServoModel("I-SUR", *limits, options_.servo_time_constant, options_.max_velocity,
                             options_.encoder_counts),
      initialJoints(options_, *limits));
  if (puncturing_) cartesian_ = std::make_unique<sim::CartesianServo>(*puncturing_, *robot_, options_.period);
  if (suturing_)
    suturing_continuity_ = std::make_unique<kinematics::ContinuousIsurSuturingIk>(
        *suturing_, std::vector<double>(robot_->jointCount(), options_.max_velocity), options_.period);
  solution_.resize(robot_->jointCount());
}

IsurSimController::~IsurSimController() { stop(); }

void IsurSimController::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void IsurSimController::stop() {
  running_.store(false);
  if (thread_.joinable()) thread_.join();
}

void IsurSimController::setExternalWrench(const KDL::Wrench& wrench, std::size_t tool) {
  const std::lock_guard lock(mutex_);
  if (tool >= external_.size())
    throw std::out_of_range("I-SUR simulated controller: tool " + std::to_string(tool) + " of a robot with " +
                            std::to_string(external_.size()) + " tools");
  external_[tool] = wrench;
}

KDL::JntArray IsurSimController::commandedJoints() const {
  const std::lock_guard lock(mutex_);
  return robot_->commanded();
}

KDL::JntArray IsurSimController::jointPositions() const {
  const std::lock_guard lock(mutex_);
  return robot_->position();
}

std::uint32_t IsurSimController::actuations() const {
  const std::lock_guard lock(mutex_);
  return actuations_;
}

bool IsurSimController::forward(const KDL::JntArray& q, KDL::Frame& tool0, KDL::Frame& tool1) noexcept {
  if (puncturing_) return puncturing_->forward(q, tool0) == kinematics::IkStatus::Ok;
  return suturing_->forward(q, tool0, tool1) == kinematics::IkStatus::Ok;
}

void IsurSimController::receiveAll() noexcept {
  std::array<std::uint8_t, isur::kMaxFrameSize + 1> buffer;
  for (;;) {
    bool truncated = false;
    Endpoint from;
    const std::size_t n = socket_.receive(buffer, truncated, &from);
    if (n == 0) return;
    if (truncated) {
      counters_.count(n == 1 ? wire::DecodeStatus::Truncated : wire::DecodeStatus::BadLength);
      continue;
    }
    isur::Command command;
    wire::FrameHeader header;
    wire::DecodeStatus status = isur::decode(std::span<const std::uint8_t>(buffer.data(), n), command, header);
    if (status == wire::DecodeStatus::Ok && command.type == isur::MessageType::JointCommand &&
        command.joint_count != robot_->jointCount())
      status = wire::DecodeStatus::WrongJointCount;
    if (status == wire::DecodeStatus::Ok && command.type == isur::MessageType::CartesianCommand &&
        command.tool_count != options_.tools)
      status = wire::DecodeStatus::WrongToolCount;
    counters_.count(status);
    if (status != wire::DecodeStatus::Ok) continue;
    if (options_.server_port == 0) {
      server_ = from;
      server_known_ = true;
    }
    const std::lock_guard lock(mutex_);
    apply(command);
  }
}

void IsurSimController::apply(const isur::Command& command) noexcept {
  switch (command.type) {
    case isur::MessageType::JointCommand:
      robot_->command(std::span<const double>(command.joints.data(), command.joint_count));
      held_ = discontinuous_ = false;
      break;
    case isur::MessageType::CartesianCommand: commandPoses(command); break;
    case isur::MessageType::ToolActuation: actuate(command.actuation); break;
    case isur::MessageType::State: break;
  }
}

void IsurSimController::commandPoses(const isur::Command& command) noexcept {
  // The server repeats its latest command: the same poses again are a zero step.
  kinematics::IkStatus ik = kinematics::IkStatus::Ok;
  if (cartesian_) {
    const sim::CartesianCommandStatus outcome = cartesian_->command(toFrame(command.poses[0]));
    held_ = outcome.holding;
    discontinuous_ = outcome.holding && outcome.ik == kinematics::IkStatus::Discontinuous;
    return;
  }
  // Two tools: a tool without a new target keeps the pose of the current joint command.
  const KDL::JntArray& current = robot_->commanded();
  KDL::Frame targets[2];
  if (!forward(current, targets[0], targets[1])) ik = kinematics::IkStatus::BadInput;
  for (std::size_t t = 0; t < 2; ++t)
    if ((command.tool_mask >> t) & 1U) targets[t] = toFrame(command.poses[t]);
  if (ik == kinematics::IkStatus::Ok) ik = suturing_continuity_->solve(targets[0], targets[1], current, solution_);
  if (ik == kinematics::IkStatus::Ok && !robot_->command(solution_)) ik = kinematics::IkStatus::BadInput;
  held_ = ik != kinematics::IkStatus::Ok;
  discontinuous_ = ik == kinematics::IkStatus::Discontinuous;
}

void IsurSimController::actuate(const isur::Actuation& actuation) noexcept {
  if (actuation.request == last_request_) return;  // a repeat of a request already handled
  last_request_ = actuation.request;
  request_refused_ = options_.tools < 2 || actuation.tool != 0 || actuation_left_ > 0.0;
  if (!request_refused_) actuation_left_ = options_.actuation_time;
}

void IsurSimController::stepAndSend(double dt) noexcept {
  isur::State state;
  {
    const std::lock_guard lock(mutex_);
    robot_->step(dt);
    if (actuation_left_ > 0.0) {
      actuation_left_ -= dt;
      if (actuation_left_ <= 1e-12) {
        actuation_left_ = 0.0;
        ++actuations_;
      }
    }
    state.joint_count = static_cast<std::uint16_t>(robot_->jointCount());
    state.tool_count = options_.tools;
    for (unsigned i = 0; i < robot_->jointCount(); ++i) state.joints[i] = robot_->measured()(i);
    KDL::Frame poses[2];
    if (forward(robot_->measured(), poses[0], poses[1])) {
      for (std::size_t t = 0; t < options_.tools; ++t) toPose(poses[t], state.tools[t].pose);
      state.flags |= isur::kPoseValid;
    }
    for (std::size_t t = 0; t < options_.tools; ++t) {
      const sim::ForceTorqueReading& reading = sensors_[t].step(dt, external_[t]);
      if (reading.anySaturated()) state.flags |= isur::wrenchSaturatedFlag(t);
      for (unsigned i = 0; i < 6; ++i) state.tools[t].wrench[i] = reading.wrench(static_cast<int>(i));
    }
    if (held_) state.flags |= isur::kCartesianHeld;
    if (discontinuous_) state.flags |= isur::kCartesianDiscontinuous;
    if (actuation_left_ > 0.0) state.flags |= isur::kActuating;
    if (request_refused_) state.flags |= isur::kActuationRefused;
    state.actuations = actuations_;
    state.actuation_request = last_request_;
  }
  if (!sending_.load() || !server_known_) return;
  std::array<std::uint8_t, isur::kMaxFrameSize> out;
  const std::size_t size =
      isur::encode(state, {++sequence_, static_cast<std::uint64_t>(steadyNanoseconds())}, out);
  if (size > 0 && socket_.sendTo(server_, std::span<const std::uint8_t>(out.data(), size))) states_sent_.fetch_add(1);
}

void IsurSimController::run() noexcept {
  const auto period = std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(options_.period * 1e9)));
  auto next = std::chrono::steady_clock::now() + period;
  while (running_.load(std::memory_order_relaxed)) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(next - std::chrono::steady_clock::now());
    waitReadable(socket_.fd(), static_cast<int>(std::max<std::int64_t>(0, left.count())));
    receiveAll();
    if (std::chrono::steady_clock::now() < next) continue;
    stepAndSend(options_.period);
    next += period;
    // After a stall (a loaded machine), do not try to catch up with a burst of steps.
    if (next < std::chrono::steady_clock::now()) next = std::chrono::steady_clock::now() + period;
  }
}

}  // namespace cobra::bridges
