#include "cobra/components/planning/state_validator_component.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace cobra::components {

StateValidatorComponent::StateValidatorComponent(std::string name)
    : PlanningSceneComponent(std::move(name),
                             "State validator (thesis §5.4.2): passes teleoperation set-point pairs on only when they "
                             "are reachable and collision-free, holds the last valid pair otherwise") {
  addEventPort(in_1_);
  addEventPort(in_2_);
  addPort(out_1_);
  addPort(out_2_);
  addPort(held_1_);
  addPort(held_2_);
  addPort(min_distance_);
  addOperation("lastReason", std::function<std::string()>([this] {
                 return last_rejected_.valid() ? std::string() : planning::describe(last_rejected_);
               }),
               "why the last rejected set-point pair was rejected (empty before any)");
}

StateValidatorComponent::~StateValidatorComponent() = default;

bool StateValidatorComponent::configureHook() {
  try {
    validator_ = buildValidator();
  } catch (const std::invalid_argument& error) {
    return refuse(error.what());
  }
  return true;
}

bool StateValidatorComponent::startHook() {
  have_1_ = have_2_ = have_valid_ = false;
  was_valid_ = true;
  last_rejected_ = planning::ValidityResult{};
  validator_->resetWarmStart();
  return true;
}

void StateValidatorComponent::cleanupHook() { validator_.reset(); }

void StateValidatorComponent::updateHook() {
  const core::FlowStatus s1 = in_1_.read(incoming_.first);
  const core::FlowStatus s2 = in_2_.read(incoming_.second);
  have_1_ = have_1_ || s1 != core::FlowStatus::NoData;
  have_2_ = have_2_ || s2 != core::FlowStatus::NoData;
  if (!have_1_ || !have_2_) return;
  if (s1 != core::FlowStatus::NewData && s2 != core::FlowStatus::NewData) return;
  // The check stops at the first pair under the threshold; for a valid pair the robots are placed
  // and the exact minimum over the checked pairs is computed from the world.
  const planning::ValidityResult result = validator_->check(incoming_);
  double minimum = std::numeric_limits<double>::quiet_NaN();
  if (result.valid()) {
    minimum = std::numeric_limits<double>::infinity();
    const planning::SceneDescription& scene = validator_->scene();
    for (const planning::GroupPair& pair : scene.checks)
      minimum = std::min(minimum, validator_->world().distance(pair.first, pair.second).distance);
    last_valid_ = incoming_;
    have_valid_ = true;
    if (!was_valid_) emitEvent("e_state_valid");
    was_valid_ = true;
  } else {
    if (result.validity == planning::Validity::TooClose) minimum = result.distance;
    last_rejected_ = result;
    if (was_valid_) emitEvent("e_state_invalid");
    was_valid_ = false;
    if (have_valid_) {  // the robot stays at the last valid pair: the set-points' producers re-sync to it
      held_1_.write(last_valid_.first);
      held_2_.write(last_valid_.second);
    }
  }
  min_distance_.write(minimum);
  if (have_valid_) {
    out_1_.write(last_valid_.first);
    out_2_.write(last_valid_.second);
  }
}

}  // namespace cobra::components
