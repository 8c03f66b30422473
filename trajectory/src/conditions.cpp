#include "cobra/trajectory/conditions.hpp"

#include "checks.hpp"

namespace cobra::trajectory {

namespace {

void requireFiniteState(const State& s, const char* side) {
  detail::requireFinite(s.position, "Conditions: ", side, " position");
  detail::requireFinite(s.velocity, "Conditions: ", side, " velocity");
  detail::requireFinite(s.acceleration, "Conditions: ", side, " acceleration");
  detail::requireFinite(s.jerk, "Conditions: ", side, " jerk");
}

}  // namespace

Conditions::Conditions(double initial_position, double final_position)
    : Conditions(State{initial_position}, State{final_position}) {}

Conditions::Conditions(const State& initial, const State& final) : initial_(initial), final_(final) {
  requireFiniteState(initial_, "initial");
  requireFiniteState(final_, "final");
}

}  // namespace cobra::trajectory
