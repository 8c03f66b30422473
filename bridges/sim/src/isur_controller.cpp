#include "cobra/bridges/sim/isur_controller.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/bridges/isur_udp_server.hpp"

namespace cobra::bridges {

namespace {

const IsurSimControllerOptions& checked(const IsurSimControllerOptions& o) {
  if (!(o.period > 0.0 && o.period <= 0.1))
    throw std::runtime_error("I-SUR simulated controller: period is " + std::to_string(o.period) +
                             " s: give (0, 0.1]");
  return o;
}

std::vector<double> middleOf(const kinematics::JointLimits& limits) {
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
      sensor_(sim::atiNano17(), options_.seed) {
  robot_ = std::make_unique<sim::ServoRobot>(
      sim::uniformServoModel("I-SUR", solver_.limits(), options_.servo_time_constant, options_.max_velocity,
                             options_.encoder_counts),
      middleOf(solver_.limits()));
  cartesian_ = std::make_unique<sim::CartesianServo>(solver_, *robot_, options_.period);
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

void IsurSimController::setExternalWrench(const KDL::Wrench& wrench) {
  const std::lock_guard lock(mutex_);
  external_ = wrench;
}

KDL::JntArray IsurSimController::commandedJoints() const {
  const std::lock_guard lock(mutex_);
  return robot_->commanded();
}

KDL::JntArray IsurSimController::jointPositions() const {
  const std::lock_guard lock(mutex_);
  return robot_->position();
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
    counters_.count(status);
    if (status != wire::DecodeStatus::Ok) continue;
    if (options_.server_port == 0) {
      server_ = from;
      server_known_ = true;
    }
    const std::lock_guard lock(mutex_);
    if (command.type == isur::MessageType::JointCommand) {
      robot_->command(std::span<const double>(command.joints.data(), command.joint_count));
      held_ = discontinuous_ = false;
    } else {
      // The server repeats its latest command: the same pose again is a zero step.
      const sim::CartesianCommandStatus outcome = cartesian_->command(toFrame(command.pose));
      held_ = outcome.holding;
      discontinuous_ = outcome.holding && outcome.ik == kinematics::IkStatus::Discontinuous;
    }
  }
}

void IsurSimController::stepAndSend(double dt) noexcept {
  isur::State state;
  {
    const std::lock_guard lock(mutex_);
    robot_->step(dt);
    const sim::ForceTorqueReading& reading = sensor_.step(dt, external_);
    state.joint_count = static_cast<std::uint16_t>(robot_->jointCount());
    for (unsigned i = 0; i < robot_->jointCount(); ++i) state.joints[i] = robot_->measured()(i);
    KDL::Frame pose;
    if (solver_.forward(robot_->measured(), pose) == kinematics::IkStatus::Ok) {
      toPose(pose, state.pose);
      state.flags |= isur::kPoseValid;
    }
    if (reading.anySaturated()) state.flags |= isur::kWrenchSaturated;
    if (held_) state.flags |= isur::kCartesianHeld;
    if (discontinuous_) state.flags |= isur::kCartesianDiscontinuous;
    for (unsigned i = 0; i < 6; ++i) state.wrench[i] = reading.wrench(static_cast<int>(i));
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
