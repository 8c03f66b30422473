#include "cobra/bridges/isur_robot_bridge.hpp"

#include <algorithm>
#include <cmath>

#include "cobra/core/error.hpp"

namespace cobra::bridges {

namespace {

std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }

void toPose(const KDL::Frame& frame, isur::Pose& pose) noexcept {
  for (int i = 0; i < 3; ++i) pose.position[static_cast<std::size_t>(i)] = frame.p(i);
  frame.M.GetQuaternion(pose.quaternion[0], pose.quaternion[1], pose.quaternion[2], pose.quaternion[3]);
}

KDL::Frame toFrame(const isur::Pose& pose) noexcept {
  const auto& q = pose.quaternion;
  return KDL::Frame(KDL::Rotation::Quaternion(q[0], q[1], q[2], q[3]),
                    KDL::Vector(pose.position[0], pose.position[1], pose.position[2]));
}

}  // namespace

ISURRobotBridge::ISURRobotBridge(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "I-SUR robot bridge (thesis §4.5.7): shared memory kept in step with the controller over UDP") {
  addPort(des_cart_pose_);
  addPort(des_joints_);
  addPort(meas_cart_pose_);
  addPort(meas_joints_);
  addPort(meas_wrench_);
  addPort(held_cart_pose_);
  addProperty(shm_name_);
  addProperty(joints_.range(1, isur::kMaxJoints));
  addProperty(tools_.range(1, isur::kMaxTools));
  addProperty(actuate_event_);
  addProperty(timeout_.range(1e-3, 3600.0));
  addProperty(run_server_);
  addProperty(controller_host_);
  addProperty(controller_port_.range(0, 65535));
  addProperty(server_port_.range(0, 65535));
  addProperty(max_delay_.range(0.0, 10.0));
  addOperation("rejectedCount", &ISURRobotBridge::rejectedCount, this,
               "state datagrams rejected for `reason` (truncated, bad_magic, bad_version, bad_type, bad_length, "
               "bad_crc, non_finite, bad_value, late, delayed, wrong_joint_count, wrong_tool_count) or \"all\"",
               core::ExecutionThread::Client)
      .arg("reason", "", "a reason name, or all");
  addOperation("acceptedCount", &ISURRobotBridge::acceptedCount, this, "valid state datagrams received by the server",
               core::ExecutionThread::Client);
  addOperation("serverPort", &ISURRobotBridge::serverPort, this,
               "the UDP port the in-process server receives states on (0 without run_server)",
               core::ExecutionThread::Client);
  des_poses_ = {&des_cart_pose_, nullptr};
  meas_poses_ = {&meas_cart_pose_, nullptr};
  meas_wrenches_ = {&meas_wrench_, nullptr};
  held_poses_ = {&held_cart_pose_, nullptr};
}

ISURRobotBridge::~ISURRobotBridge() = default;

void ISURRobotBridge::registerToolPorts(unsigned tools) {
  if (tools == tools_registered_) return;
  const std::array<core::PortBase*, 4> one_tool{&des_cart_pose_, &meas_cart_pose_, &meas_wrench_, &held_cart_pose_};
  const std::array<core::PortBase*, 9> two_tools{&des_right_pose_,    &des_left_pose_,     &meas_right_pose_,
                                                 &meas_left_pose_,    &meas_right_wrench_, &meas_left_wrench_,
                                                 &held_right_pose_,   &held_left_pose_,    &actuations_out_};
  if (tools == 2) {
    for (core::PortBase* p : one_tool) removePort(*p);
    for (core::PortBase* p : two_tools) addPort(*p);
    addEventPort(input_events_);
    des_poses_ = {&des_right_pose_, &des_left_pose_};
    meas_poses_ = {&meas_right_pose_, &meas_left_pose_};
    meas_wrenches_ = {&meas_right_wrench_, &meas_left_wrench_};
    held_poses_ = {&held_right_pose_, &held_left_pose_};
  } else {
    for (core::PortBase* p : two_tools) removePort(*p);
    removePort(input_events_);
    for (core::PortBase* p : one_tool) addPort(*p);
    des_poses_ = {&des_cart_pose_, nullptr};
    meas_poses_ = {&meas_cart_pose_, nullptr};
    meas_wrenches_ = {&meas_wrench_, nullptr};
    held_poses_ = {&held_cart_pose_, nullptr};
  }
  tools_registered_ = tools;
}

bool ISURRobotBridge::configureHook() {
  const auto n = static_cast<unsigned>(joints_());
  const auto tools = static_cast<unsigned>(tools_());
  if (tools == 2 && (actuate_event_().empty() || actuate_event_().size() > core::BoundedString<63>::capacity()))
    return refuse("property actuate_event is '" + actuate_event_() + "'; expected an event name of 1 to 63 characters");
  try {
    server_.reset();
    block_ = std::make_unique<SharedBlock<IsurSharedBlock>>(shm_name_());
    if (run_server_()) {
      if (controller_port_() == 0) return refuse("property controller_port is 0: give the I-SUR controller's UDP port");
      IsurUdpServerOptions options;
      options.shm_name = shm_name_();
      options.controller_host = controller_host_();
      options.controller_port = static_cast<std::uint16_t>(controller_port_());
      options.bind_port = static_cast<std::uint16_t>(server_port_());
      options.joints = static_cast<std::uint16_t>(n);
      options.tools = static_cast<std::uint16_t>(tools);
      options.max_delay = max_delay_();
      server_ = std::make_unique<IsurUdpServer>(options);
    }
  } catch (const std::exception& e) {
    block_.reset();
    return refuse(e.what());
  }
  registerToolPorts(tools);
  actuate_name_.assign(actuate_event_());
  q_in_.resize(n);
  q_out_.resize(n);
  meas_joints_.setDataSample(q_out_);
  command_ = isur::Command{};
  command_.tool_count = static_cast<std::uint16_t>(tools);
  command_.tool_mask = 0;
  return true;
}

bool ISURRobotBridge::startHook() {
  if (server_) server_->start();
  watchdog_.arm(now().count());
  last_version_ = (*block_)->state.version();  // a state left from an earlier run is not fresh
  have_state_ = false;
  refusing_ = told_failed_ = told_discontinuity_ = timed_out_ = false;
  request_open_ = have_count_ = false;
  command_.tool_mask = 0;
  core::Event stale;
  while (input_events_.readNew(stale) == core::FlowStatus::NewData) {
  }  // requests sent before the start are not this run's
  return true;
}

void ISURRobotBridge::readCommands(IsurSharedBlock& block) noexcept {
  if (des_joints_.read(q_in_) == core::FlowStatus::NewData && q_in_.rows() == q_out_.rows()) {
    bool finite = true;
    for (unsigned i = 0; i < q_in_.rows(); ++i) finite = finite && std::isfinite(q_in_(i));
    if (finite) {
      command_.type = isur::MessageType::JointCommand;
      command_.joint_count = static_cast<std::uint16_t>(q_in_.rows());
      for (unsigned i = 0; i < q_in_.rows(); ++i) command_.joints[i] = q_in_(i);
      command_.tool_mask = 0;  // tools not commanded again keep the pose of this joint command
      block.command.write(command_);
    }
  }
  bool new_pose = false;
  for (std::size_t t = 0; t < command_.tool_count; ++t) {
    KDL::Frame pose;
    if (des_poses_[t]->read(pose) != core::FlowStatus::NewData) continue;
    isur::Pose wire_pose;
    toPose(pose, wire_pose);
    if (!wire::allFinite(wire_pose.position) || !wire::allFinite(wire_pose.quaternion)) continue;
    command_.poses[t] = wire_pose;
    command_.tool_mask = static_cast<std::uint16_t>(command_.tool_mask | (1U << t));
    new_pose = true;
  }
  if (new_pose) {
    command_.type = isur::MessageType::CartesianCommand;
    block.command.write(command_);
  }
}

void ISURRobotBridge::readActuationRequests(IsurSharedBlock& block) noexcept {
  if (tools_registered_ < 2) return;
  core::Event request;
  while (input_events_.readNew(request) == core::FlowStatus::NewData) {
    if (!(request.name == actuate_name_)) continue;
    if (request_open_ || (have_state_ && (state_.flags & isur::kActuating) != 0)) {
      emitEvent("e_endo_stitch_busy");
      continue;
    }
    // A number the controller has not handled yet (it handles each number once, even across restarts).
    request_ = std::max(request_, state_.actuation_request) + 1;
    if (request_ == 0) request_ = 1;
    block.actuation.write(isur::Actuation{.tool = 0, .request = request_});
    request_open_ = true;
  }
}

void ISURRobotBridge::reportActuations() noexcept {
  if (request_open_ && state_.actuation_request == request_) {
    request_open_ = false;
    if ((state_.flags & isur::kActuationRefused) != 0) emitEvent("e_endo_stitch_busy");
  }
  if (!have_count_) {
    have_count_ = true;
    actuation_base_ = state_.actuations;
    actuations_seen_ = 0;
    actuations_out_.write(0);
    return;
  }
  const std::uint32_t count = state_.actuations - actuation_base_;
  if (count == actuations_seen_) return;
  actuations_seen_ = count;
  actuations_out_.write(static_cast<int>(count));
  emitEvent("e_endo_stitch_actuated");
}

void ISURRobotBridge::updateHook() {
  IsurSharedBlock& block = **block_;
  readCommands(block);
  readActuationRequests(block);
  const std::uint64_t version = block.state.read(state_);
  const bool fresh = version != 0 && version != last_version_ && state_.joint_count == q_out_.rows() &&
                     state_.tool_count == tools_registered_;
  if (version != 0) last_version_ = version;
  if (fresh) {
    for (unsigned i = 0; i < q_out_.rows(); ++i) q_out_(i) = state_.joints[i];
    for (std::size_t t = 0; t < tools_registered_; ++t) {
      if (state_.flags & isur::kPoseValid) pose_out_[t] = toFrame(state_.tools[t].pose);
      const auto& w = state_.tools[t].wrench;
      wrench_out_[t] = KDL::Wrench(KDL::Vector(w[0], w[1], w[2]), KDL::Vector(w[3], w[4], w[5]));
    }
    have_state_ = true;
    reportCartesianStatus(state_.flags);
    if (tools_registered_ == 2) reportActuations();
  }
  switch (watchdog_.update(fresh, now().count(), toNs(timeout_()))) {
    case CommWatchdog::Change::TimedOut:
      emitEvent("e_comm_timeout");
      timed_out_ = true;
      break;
    case CommWatchdog::Change::Restored:
      emitEvent("e_comm_restored");
      timed_out_ = false;
      break;
    case CommWatchdog::Change::None: break;
  }
  if (!have_state_) return;
  publish();
  // Held (a refused command in this state, or no state for `timeout`): where the robot is.
  if ((fresh && refusing_) || timed_out_)
    for (std::size_t t = 0; t < tools_registered_; ++t) held_poses_[t]->write(pose_out_[t]);
}

void ISURRobotBridge::reportCartesianStatus(std::uint16_t flags) {
  if ((flags & isur::kCartesianHeld) == 0) {
    if (refusing_) emitEvent("e_ik_solved");
    refusing_ = told_failed_ = told_discontinuity_ = false;
    return;
  }
  refusing_ = true;
  if ((flags & isur::kCartesianDiscontinuous) != 0) {
    if (!told_discontinuity_) emitEvent("e_ik_discontinuity");
    told_discontinuity_ = true;
  } else {
    if (!told_failed_) emitEvent("e_ik_failed");
    told_failed_ = true;
  }
}

void ISURRobotBridge::publish() {
  meas_joints_.write(q_out_);
  for (std::size_t t = 0; t < tools_registered_; ++t) {
    meas_poses_[t]->write(pose_out_[t]);
    meas_wrenches_[t]->write(wrench_out_[t]);
  }
}

void ISURRobotBridge::cleanupHook() {
  server_.reset();
  block_.reset();
}

int ISURRobotBridge::rejectedCount(std::string reason) {
  if (!block_) throw core::Error("component '" + name() + "': rejectedCount needs a configured bridge");
  const ReceiveCounters& counters = (*block_)->counters;
  if (reason == "all") return static_cast<int>(counters.rejected());
  wire::DecodeStatus status;
  if (!wire::parseDecodeStatus(reason, status) || status == wire::DecodeStatus::Ok)
    throw core::Error("component '" + name() + "': rejectedCount: unknown reason '" + reason +
                      "'; give all, truncated, bad_magic, bad_version, bad_type, bad_length, bad_crc, non_finite, "
                      "bad_value, late, delayed, wrong_joint_count or wrong_tool_count");
  return static_cast<int>(counters.get(status));
}

int ISURRobotBridge::acceptedCount() {
  if (!block_) throw core::Error("component '" + name() + "': acceptedCount needs a configured bridge");
  return static_cast<int>((*block_)->counters.accepted());
}

int ISURRobotBridge::serverPort() { return server_ ? server_->local().port() : 0; }

}  // namespace cobra::bridges
