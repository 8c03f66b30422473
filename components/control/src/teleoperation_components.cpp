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

core::Property<double> level(const char* tank, const char* which, double value, const char* doc) {
  return core::Property<double>(std::string(tank) + "_" + which, value, "J", doc);
}

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
                "Passivity layer (thesis §4.5.4): implements the coupling forces as far as two energy tanks can pay"),
      master_levels_{level("master", "minimum", 1.0, "ε: nothing is taken out below it"),
                     level("master", "request", 5.0, "T_req: below it energy is requested"),
                     level("master", "available", 10.0, "T_ava: above it energy is given"),
                     level("master", "maximum", 20.0, "T̄: nothing is stored above it"),
                     level("master", "initial", 10.0, "energy at configure")},
      slave_levels_{level("slave", "minimum", 1.0, "ε"), level("slave", "request", 5.0, "T_req"),
                    level("slave", "available", 10.0, "T_ava"), level("slave", "maximum", 20.0, "T̄"),
                    level("slave", "initial", 10.0, "energy at configure")} {
  for (auto& p : master_levels_) addProperty(p);
  for (auto& p : slave_levels_) addProperty(p);
  addProperty(transfer_power_);
  addProperty(master_max_force_);
  addProperty(master_max_torque_);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{
           &master_desired_, &slave_desired_, &master_twist_, &slave_twist_, &master_dissipation_, &slave_dissipation_,
           &master_force_, &slave_force_, &master_energy_, &slave_energy_})
    addPort(*p);
}

bool PassivityLayerComponent::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: its period is the control period");
  auto levels = [](const core::Property<double>* l) { return control::TankLevels{l[0](), l[1](), l[2](), l[3](), l[4]()}; };
  try {
    const auto limit = [](double value) { return value < 0.0 ? std::numeric_limits<double>::infinity() : value; };
    layer_.emplace(control::PassivityParameters{levels(master_levels_), levels(slave_levels_), transfer_power_(),
                                                limit(master_max_force_()), limit(master_max_torque_())});
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  return true;
}

void PassivityLayerComponent::updateHook() {
  (void)master_desired_.read(master_wanted_);
  (void)slave_desired_.read(slave_wanted_);
  (void)master_twist_.read(master_velocity_);
  (void)slave_twist_.read(slave_velocity_);
  (void)master_dissipation_.read(master_power_);
  (void)slave_dissipation_.read(slave_power_);
  const double dt = std::chrono::duration<double>(activity().period()).count();
  const control::PassivityStep out = layer_->step(dt, toEigen(master_wanted_), toEigen(slave_wanted_),
                                                  toEigen(master_velocity_), toEigen(slave_velocity_), master_power_,
                                                  slave_power_);
  if (out.master_limited && !master_limited_) emitEvent("e_master_limited");
  if (out.slave_limited && !slave_limited_) emitEvent("e_slave_limited");
  master_limited_ = out.master_limited;
  slave_limited_ = out.slave_limited;
  master_force_.write(toKdlWrench(out.master_wrench));
  slave_force_.write(toKdlWrench(out.slave_wrench));
  master_energy_.write(layer_->masterEnergy());
  slave_energy_.write(layer_->slaveEnergy());
}

}  // namespace cobra::components
