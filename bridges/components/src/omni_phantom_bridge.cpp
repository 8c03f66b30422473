#include "cobra/bridges/omni_phantom_bridge.hpp"

#include <cmath>

#include "cobra/core/error.hpp"

namespace cobra::bridges {

namespace {
std::int64_t toNs(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }
}  // namespace

OmniPhantomBridge::OmniPhantomBridge(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Phantom Omni bridge (thesis §4.5.9): TCP client of the stand-alone Omni application") {
  addPort(des_wrench_);
  addPort(meas_cart_pose_);
  addPort(meas_twist_);
  addPort(status_buttons_);
  addProperty(host_address_);
  addProperty(host_port_.range(0, 65535));
  addProperty(origin_pose_offset_);
  addProperty(timeout_.range(1e-3, 3600.0));
  addProperty(max_delay_.range(0.0, 10.0));
  addProperty(reconnect_period_.range(1e-3, 10.0));
  addOperation("rejectedCount", &OmniPhantomBridge::rejectedCount, this,
               "state frames rejected for `reason` (truncated, bad_magic, bad_version, bad_type, bad_length, "
               "bad_crc, non_finite, bad_value, late, delayed) or \"all\"",
               core::ExecutionThread::Client)
      .arg("reason", "", "a reason name, or all");
  addOperation("acceptedCount", &OmniPhantomBridge::acceptedCount, this, "valid state frames received",
               core::ExecutionThread::Client);
  addOperation("connections", &OmniPhantomBridge::connections, this,
               "successful connections to the application so far (reconnections included)",
               core::ExecutionThread::Client);
}

OmniPhantomBridge::~OmniPhantomBridge() = default;

bool OmniPhantomBridge::configureHook() {
  if (host_port_() == 0) return refuse("property host_port is 0: give the Omni application's TCP port");
  try {
    OmniClientOptions options;
    options.host = host_address_();
    options.port = static_cast<std::uint16_t>(host_port_());
    options.max_delay = max_delay_();
    options.reconnect_period = reconnect_period_();
    client_ = std::make_unique<OmniClient>(options);
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  return true;
}

bool OmniPhantomBridge::startHook() {
  client_->start();
  watchdog_.arm(now().count());
  last_version_ = client_->state.version();
  have_state_ = false;
  return true;
}

void OmniPhantomBridge::updateHook() {
  offset_ = origin_pose_offset_();
  KDL::Wrench wrench;
  if (des_wrench_.read(wrench) == core::FlowStatus::NewData) {
    const KDL::Vector f = offset_.M.Inverse(wrench.force);
    const KDL::Vector t = offset_.M.Inverse(wrench.torque);
    omni::WrenchCommand command{{f.x(), f.y(), f.z(), t.x(), t.y(), t.z()}};
    if (wire::allFinite(command.wrench)) client_->command.write(command);
  }
  omni::State state;
  const std::uint64_t version = client_->state.read(state);
  const bool fresh = version != 0 && version != last_version_;
  if (version != 0) last_version_ = version;
  if (fresh) {
    const auto& q = state.quaternion;
    const KDL::Frame device(KDL::Rotation::Quaternion(q[0], q[1], q[2], q[3]),
                            KDL::Vector(state.position[0], state.position[1], state.position[2]));
    pose_ = offset_ * device;
    const auto& v = state.twist;
    twist_ = KDL::Twist(offset_.M * KDL::Vector(v[0], v[1], v[2]), offset_.M * KDL::Vector(v[3], v[4], v[5]));
    buttons_ = static_cast<int>(state.buttons);
    have_state_ = true;
  }
  switch (watchdog_.update(fresh, now().count(), toNs(timeout_()))) {
    case CommWatchdog::Change::TimedOut: emitEvent("e_comm_timeout"); break;
    case CommWatchdog::Change::Restored: emitEvent("e_comm_restored"); break;
    case CommWatchdog::Change::None: break;
  }
  if (have_state_) {
    meas_cart_pose_.write(pose_);
    meas_twist_.write(twist_);
    status_buttons_.write(buttons_);
  }
}

void OmniPhantomBridge::stopHook() { client_->stop(); }

void OmniPhantomBridge::cleanupHook() { client_.reset(); }

int OmniPhantomBridge::rejectedCount(std::string reason) {
  if (!client_) throw core::Error("component '" + name() + "': rejectedCount needs a configured bridge");
  if (reason == "all") return static_cast<int>(client_->counters().rejected());
  wire::DecodeStatus status;
  if (!wire::parseDecodeStatus(reason, status) || status == wire::DecodeStatus::Ok)
    throw core::Error("component '" + name() + "': rejectedCount: unknown reason '" + reason +
                      "'; give all, truncated, bad_magic, bad_version, bad_type, bad_length, bad_crc, non_finite, "
                      "bad_value, late or delayed");
  return static_cast<int>(client_->counters().get(status));
}

int OmniPhantomBridge::acceptedCount() {
  if (!client_) throw core::Error("component '" + name() + "': acceptedCount needs a configured bridge");
  return static_cast<int>(client_->counters().accepted());
}

int OmniPhantomBridge::connections() { return client_ ? static_cast<int>(client_->connections()) : 0; }

}  // namespace cobra::bridges
