#include "cobra/components/drivers/puma260_ethercat_master.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/core/backend_registry.hpp"
#include "cobra/kinematics/puma260.hpp"

namespace cobra::components {
namespace {

// Corke's Puma "ready" pose qr (arm straight up) and nominal pose qn, in kinematics/puma260.hpp's
// DH convention. ASSUMPTION: the thesis gives neither joint vector; qn stands in for the nest.
const std::vector<double> kReady = {0.0, 1.5707963267948966, -1.5707963267948966, 0.0, 0.0, 0.0};
const std::vector<double> kNest = {0.0, 0.7853981633974483, -3.141592653589793, 0.0, 0.7853981633974483, 0.0};

std::vector<double> limitVector(bool upper) {
  const kinematics::JointLimits limits = kinematics::Puma260Solver::defaultLimits();
  return upper ? limits.upper : limits.lower;
}

/// Copies a 6-element property; the message names the property and what it needs.
bool joints(const core::Property<std::vector<double>>& p, fieldbus::JointVector& out, std::string& why) {
  if (p().size() != 6) {
    why =
        "property " + p.name() + " has " + std::to_string(p().size()) + " numbers; give 6 joint values in " + p.unit();
    return false;
  }
  for (std::size_t i = 0; i < 6; ++i) out[i] = p()[i];
  return true;
}

}  // namespace

Puma260EtherCATMaster::Puma260EtherCATMaster(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Puma 260 EtherCAT master (thesis §6.2.1): six CiA 402 drives, nest/ready/operative states") {
  nest_.set(kNest);
  ready_.set(kReady);
  lower_.set(limitVector(false));
  upper_.set(limitVector(true));
  for (core::PropertyBase* p :
       std::initializer_list<core::PropertyBase*>{&bus_, &control_mode_, &nest_, &ready_, &move_speed_, &tolerance_,
                                                  &lower_, &upper_, &max_velocity_, &max_torque_})
    addProperty(*p);
  for (core::PortBase* p :
       std::initializer_list<core::PortBase*>{&des_position_, &des_velocity_, &des_torque_, &meas_position_,
                                              &meas_velocity_, &meas_torque_, &held_position_, &current_state_})
    addPort(*p);
  for (auto* port : {&meas_position_, &meas_velocity_, &meas_torque_, &held_position_})
    port->setDataSample(KDL::JntArray(6));
  addOperation("askReady", std::function<void()>([this] { ask(fieldbus::Request::Ready); }),
               "move to the ready position (from Initialized, NestPosition, ReadyPosition or Operative); "
               "e_ready_reached when there, e_request_refused otherwise");
  addOperation("askNest", std::function<void()>([this] { ask(fieldbus::Request::Nest); }),
               "move to the nest position (only from ReadyPosition); e_nest_reached when there");
  addOperation("askOperative", std::function<void()>([this] { ask(fieldbus::Request::Operative); }),
               "enter Operative (only from ReadyPosition); e_operative");
  addOperation("askFaultReset", std::function<void()>([this] { ask(fieldbus::Request::FaultReset); }),
               "reset the drives' faults (only in Fault); e_fault_reset, then e_initialized");
  addOperation("busFault", std::function<std::string()>([this] { return busFault(); }),
               "the last working-counter mismatch (expected and received counter), or that there was none");
  addOperation("slaveStatus", std::function<std::string(int)>([this](int i) { return slaveStatus(i); }),
               "one line about slave i (0-5)")
      .arg("slave", "1", "slave index, 0-5");
}

Puma260EtherCATMaster::~Puma260EtherCATMaster() = default;

bool Puma260EtherCATMaster::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: its period is the EtherCAT cycle");
  fieldbus::Puma260MasterConfig config;
  if (!fieldbus::parseControlMode(control_mode_().c_str(), config.control_mode))
    return refuse("property control_mode is '" + control_mode_() + "'; expected position, velocity or torque");
  std::string why;
  if (!joints(nest_, config.nest, why) || !joints(ready_, config.ready, why) || !joints(lower_, config.lower, why) ||
      !joints(upper_, config.upper, why))
    return refuse(why);
  config.move_speed = move_speed_();
  config.position_tolerance = tolerance_();
  config.max_velocity = max_velocity_();
  config.max_torque = max_torque_();
  std::shared_ptr<fieldbus::Cia402Bus> bus;
  try {
    bus = core::BackendRegistry<fieldbus::Cia402Bus>::open(bus_());
  } catch (const std::exception& e) {
    return refuse("property bus = '" + bus_() + "': " + e.what());
  }
  try {
    master_.emplace(config, *bus);
  } catch (const std::invalid_argument& e) {
    master_.reset();
    bus_device_.reset();
    return refuse(e.what());
  }
  bus_device_ = std::move(bus);
  commands_ = {};
  published_ = master_->state();
  current_state_.write(core::TaskState{fieldbus::toString(published_)});
  return true;
}

void Puma260EtherCATMaster::cleanupHook() {
  master_.reset();
  bus_device_.reset();
}

void Puma260EtherCATMaster::ask(fieldbus::Request request) {
  if (!master_ || !master_->request(request)) emitEvent("e_request_refused");
}

std::string Puma260EtherCATMaster::busFault() const {
  if (!master_) return "not configured: no bus";
  const fieldbus::WorkingCounter wc = master_->workingCounterFault();
  if (wc.expected == 0 && wc.received == 0) return "no working-counter mismatch";
  return "working counter " + std::to_string(wc.received) + ", expected " + std::to_string(wc.expected) +
         ": a slave did not process its datagram (the master quick-stopped every drive)";
}

std::string Puma260EtherCATMaster::slaveStatus(int slave) const {
  if (!bus_device_) return "not configured: no bus";
  const std::string line = bus_device_->describeSlave(slave);
  if (!master_ || slave < 0 || slave > 5) return line;
  return line + ", master sees " + fieldbus::cia402::toString(master_->sequencer(slave).state());
}

namespace {
/// A joint that moved less than kStillBand (rad) for kStillTime (s) is at rest: the quick stop has
/// ended (a few encoder counts; 0.1 s of 1 ms cycles).
constexpr double kStillBand = 1e-4;
constexpr double kStillTime = 0.1;
}  // namespace

void Puma260EtherCATMaster::updateHook() {
  // A sample with another size than 6 is ignored (restoring the buffer's size is the only allocation,
  // and only on such bad input). A non-finite one never reaches the drives: the last finite command
  // holds, and e_command_not_finite is told once per episode.
  bool refused = false, finite_taken = false;
  const auto take = [&](core::InputPort<KDL::JntArray>& port, fieldbus::JointVector& into, bool& valid) {
    if (port.read(scratch_) != core::FlowStatus::NewData) return;
    if (scratch_.rows() != 6) {
      scratch_.resize(6);
      return;
    }
    for (unsigned i = 0; i < 6; ++i)
      if (!std::isfinite(scratch_(i))) {
        refused = true;
        return;
      }
    for (unsigned i = 0; i < 6; ++i) into[i] = scratch_(i);
    valid = true;
    finite_taken = true;
  };
  take(des_position_, commands_.position, commands_.position_valid);
  take(des_velocity_, commands_.velocity, commands_.velocity_valid);
  take(des_torque_, commands_.torque, commands_.torque_valid);
  if (refused && !refusing_non_finite_) emitEvent("e_command_not_finite");
  if (refused) refusing_non_finite_ = true;
  else if (finite_taken) refusing_non_finite_ = false;
  const double dt = std::chrono::duration<double>(activity().period()).count();
  const std::uint32_t events = master_->step(dt, commands_);
  namespace ev = fieldbus::master_event;
  if (events & ev::kDriveFault) emitEvent("e_drive_fault");
  if (events & ev::kBusError) emitEvent("e_bus_error");
  if (events & ev::kWorkingCounterMismatch) emitEvent("e_bus_fault");
  if (events & ev::kFaultReset) emitEvent("e_fault_reset");
  if (events & ev::kInitialized) emitEvent("e_initialized");
  if (events & ev::kReadyReached) emitEvent("e_ready_reached");
  if (events & ev::kNestReached) emitEvent("e_nest_reached");
  if (events & ev::kOperative) emitEvent("e_operative");
  if (events & ev::kCommandClamped) emitEvent("e_command_clamped");
  const auto publish = [this](core::OutputPort<KDL::JntArray>& port, const fieldbus::JointVector& values) {
    for (unsigned i = 0; i < 6; ++i) out_(i) = values[i];
    port.write(out_);
  };
  publish(meas_position_, master_->position());
  publish(meas_velocity_, master_->velocity());
  publish(meas_torque_, master_->torque());
  // Held once the quick stop has brought every joint to rest (none moved more than kStillBand for
  // kStillTime; the encoders' velocity reads 0 between counts, so one sample cannot tell): where
  // the robot stays.
  if (master_->state() == fieldbus::MasterState::Fault) {
    const fieldbus::JointVector& q = master_->position();
    bool still = true;
    for (unsigned i = 0; i < 6; ++i) still = still && std::abs(q[i] - rest_position_[i]) <= kStillBand;
    if (still) {
      still_time_ += dt;
    } else {
      rest_position_ = q;
      still_time_ = 0.0;
    }
    if (still_time_ >= kStillTime) publish(held_position_, q);
  } else {
    still_time_ = 0.0;
  }
  if (master_->state() != published_) {  // also the changes made by the ask operations
    published_ = master_->state();
    current_state_.write(core::TaskState{fieldbus::toString(published_)});
  }
  if (master_->state() != fieldbus::MasterState::Operative) {
    // Commands given before Operative do not act when it is entered: each mode starts by holding.
    commands_.position_valid = commands_.velocity_valid = commands_.torque_valid = false;
  }
}

}  // namespace cobra::components
