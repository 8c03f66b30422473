#include "cobra/components/control/link_impairment_component.hpp"

#include <chrono>
#include <limits>
#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {
namespace {

int clamped(std::uint64_t count) noexcept {
  return count > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ? std::numeric_limits<int>::max()
                                                                              : static_cast<int>(count);
}

}  // namespace

LinkImpairmentComponent::LinkImpairmentComponent(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "impaired master-slave link (thesis §4.5.4): delay, jitter and loss on a teleoperation coupling") {
  for (core::PropertyBase* p : std::initializer_list<core::PropertyBase*>{&delay_, &jitter_, &loss_, &seed_, &capacity_})
    addProperty(*p);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{
           &master_pose_, &master_twist_, &slave_wrench_, &linked_pose_, &linked_twist_, &linked_wrench_,
           &master_energy_, &master_request_, &slave_energy_, &slave_request_, &linked_master_energy_,
           &linked_master_request_, &linked_slave_energy_, &linked_slave_request_,
           &lost_forward_, &lost_backward_, &late_forward_, &late_backward_, &refused_forward_, &refused_backward_})
    addPort(*p);
}

bool LinkImpairmentComponent::configureHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update sends one packet per direction");
  if (capacity_() < 1) return refuse("property capacity is " + std::to_string(capacity_()) + "; expected >= 1 packets");
  control::LinkImpairmentParameters p;
  p.delay = delay_();
  p.jitter = jitter_();
  p.loss = loss_();
  p.seed = static_cast<std::uint64_t>(seed_());
  p.capacity = static_cast<std::size_t>(capacity_());
  try {
    forward_.emplace(p);
    p.seed += 1;
    backward_.emplace(p);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());  // names the property and its rule
  }
  master_ = arrived_master_ = MasterSample{};
  slave_ = arrived_slave_ = SlaveSample{};
  return true;
}

void LinkImpairmentComponent::cleanupHook() {
  forward_.reset();
  backward_.reset();
}

void LinkImpairmentComponent::updateHook() {
  const double time = std::chrono::duration<double>(now()).count();
  if (master_pose_.read(master_.pose) != core::FlowStatus::NoData) master_.has_pose = true;
  (void)master_twist_.read(master_.twist);
  if (slave_wrench_.read(slave_.wrench) != core::FlowStatus::NoData) slave_.has_wrench = true;
  // An energy sample goes out once: not new now, the packet carries 0 J (never twice the same).
  if (master_energy_.readNew(master_.energy) != core::FlowStatus::NewData) master_.energy = 0.0;
  if (slave_energy_.readNew(slave_.energy) != core::FlowStatus::NewData) slave_.energy = 0.0;
  // A wired tank's packets travel every period, before the first pose or wrench too (the
  // exchange needs no pose; a request that ended must be told as well).
  const bool master_energy = master_request_.read(master_.request) != core::FlowStatus::NoData || master_.energy > 0.0;
  const bool slave_energy = slave_request_.read(slave_.request) != core::FlowStatus::NoData || slave_.energy > 0.0;
  if (master_.has_pose || master_energy) (void)forward_->send(time, master_);
  if (slave_.has_wrench || slave_energy) (void)backward_->send(time, slave_);
  if (forward_->receive(time, arrived_master_)) {
    if (arrived_master_.has_pose) {
      linked_pose_.write(arrived_master_.pose);
      linked_twist_.write(arrived_master_.twist);
    }
    linked_master_energy_.write(arrived_master_.energy);
    linked_master_request_.write(arrived_master_.request);
  }
  if (backward_->receive(time, arrived_slave_)) {
    if (arrived_slave_.has_wrench) linked_wrench_.write(arrived_slave_.wrench);
    linked_slave_energy_.write(arrived_slave_.energy);
    linked_slave_request_.write(arrived_slave_.request);
  }
  lost_forward_.write(clamped(forward_->lost()));
  lost_backward_.write(clamped(backward_->lost()));
  late_forward_.write(clamped(forward_->discardedLate()));
  late_backward_.write(clamped(backward_->discardedLate()));
  refused_forward_.write(clamped(forward_->overflowed()));
  refused_backward_.write(clamped(backward_->overflowed()));
}

}  // namespace cobra::components
