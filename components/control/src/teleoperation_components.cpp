#include "cobra/components/control/teleoperation_components.hpp"

#include <chrono>
#include <limits>
#include <stdexcept>

#include "cobra/core/activity.hpp"
#include "cobra/kinematics/geometry.hpp"

namespace cobra::components {
namespace {

using kinematics::toEigen;  // [linear; angular], as the layers take them
using kinematics::toKdlWrench;

}  // namespace

TransparencyLayerComponent::TransparencyLayerComponent(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Transparency layer (thesis §4.5.4): the coupling forces master and slave should get") {
  for (core::PropertyBase* p : std::initializer_list<core::PropertyBase*>{
           &stiffness_, &damping_, &rotational_stiffness_, &rotational_damping_, &compensation_time_, &error_low_,
           &error_high_, &rest_low_, &rest_high_, &rotation_error_low_, &rotation_error_high_, &rotation_rest_low_,
           &rotation_rest_high_})
    addProperty(*p);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{&master_pose_, &master_twist_, &slave_pose_,
                                                                  &slave_twist_, &master_force_, &slave_force_})
    addPort(*p);
  addOperation("engage", &TransparencyLayerComponent::engage, this,
               "switch to teleoperation now: the current master-slave offset is compensated over compensation_time");
}

double TransparencyLayerComponent::seconds() const { return std::chrono::duration<double>(now()).count(); }

bool TransparencyLayerComponent::configureHook() {
  try {
    layer_.emplace(control::TransparencyParameters{
        stiffness_(), damping_(), rotational_stiffness_(), rotational_damping_(), compensation_time_(), error_low_(),
        error_high_(), rest_low_(), rest_high_(), rotation_error_low_(), rotation_error_high_(), rotation_rest_low_(),
        rotation_rest_high_()});
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  return true;
}

void TransparencyLayerComponent::engage() {
  (void)master_pose_.read(master_);
  (void)slave_pose_.read(slave_);
  layer_->engage(seconds(), master_, slave_);
}

void TransparencyLayerComponent::updateHook() {
  (void)master_pose_.read(master_);
  (void)slave_pose_.read(slave_);
  (void)master_twist_.read(master_velocity_);
  (void)slave_twist_.read(slave_velocity_);
  control::Vector6 fm, fs;
  layer_->compute(seconds(), master_, toEigen(master_velocity_), slave_, toEigen(slave_velocity_), fm, fs);
  master_force_.write(toKdlWrench(fm));
  slave_force_.write(toKdlWrench(fs));
}

PassivityLayerComponent::PassivityLayerComponent(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "one side's Passivity layer (thesis §4.5.4): implements its robot's coupling force as far as its "
                "energy tank can pay; the tanks exchange energy in packets over the link"),
      levels_{core::Property<double>("minimum", 1.0, "J", "ε: nothing is taken out below it"),
              core::Property<double>("request", 5.0, "J", "T_req: below it energy is requested"),
              core::Property<double>("available", 10.0, "J", "T_ava: above it energy is given"),
              core::Property<double>("maximum", 20.0, "J", "T̄: nothing is stored above it"),
              core::Property<double>("initial", 10.0, "J", "energy at configure")} {
  for (auto& p : levels_) addProperty(p);
  addProperty(transfer_power_);
  addProperty(max_force_);
  addProperty(max_torque_);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{&desired_, &twist_, &dissipation_, &energy_in_,
                                                                  &peer_request_, &force_, &energy_out_, &request_,
                                                                  &tank_energy_})
    addPort(*p);
}

bool PassivityLayerComponent::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: its period is the control period");
  try {
    const auto limit = [](double value) { return value < 0.0 ? std::numeric_limits<double>::infinity() : value; };
    layer_.emplace(control::PassivitySideParameters{
                       control::TankLevels{levels_[0](), levels_[1](), levels_[2](), levels_[3](), levels_[4]()},
                       transfer_power_(), limit(max_force_()), limit(max_torque_())},
                   "");
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  limited_ = false;
  return true;
}

void PassivityLayerComponent::updateHook() {
  // The other side's packets: each sample written on energyIn is one packet, taken once (readNew:
  // a sample read again would count its energy twice).
  while (energy_in_.readNew(arrived_) == core::FlowStatus::NewData) {
    (void)peer_request_.read(peer_asks_);
    layer_->receive(control::EnergyPacket{arrived_, peer_asks_});
  }
  if (peer_request_.readNew(peer_asks_) == core::FlowStatus::NewData)
    layer_->receive(control::EnergyPacket{0.0, peer_asks_});
  (void)desired_.read(wanted_);
  (void)twist_.read(velocity_);
  (void)dissipation_.read(power_);
  const double dt = std::chrono::duration<double>(activity().period()).count();
  const control::PassivitySideStep out = layer_->step(dt, toEigen(wanted_), toEigen(velocity_), power_);
  if (out.limited && !limited_) emitEvent("e_force_limited");
  limited_ = out.limited;
  force_.write(toKdlWrench(out.wrench));
  energy_out_.write(out.packet.energy);
  request_.write(out.packet.request);
  tank_energy_.write(layer_->energy());
}

}  // namespace cobra::components
