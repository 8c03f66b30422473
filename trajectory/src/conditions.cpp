#include "cobra/trajectory/conditions.hpp"

#include <string>

#include "checks.hpp"

namespace cobra::trajectory {

namespace {

void requireFiniteState(const State& s, const char* side) {
  const std::string where = std::string("Conditions: ") + side + " ";
  detail::requireFinite(s.position, where + "position");
  detail::requireFinite(s.velocity, where + "velocity");
  detail::requireFinite(s.acceleration, where + "acceleration");
  detail::requireFinite(s.jerk, where + "jerk");
}

}  // namespace

Conditions::Conditions(double initial_position, double final_position)
    : Conditions(State{initial_position}, State{final_position}) {}

Conditions::Conditions(const State& initial, const State& final) : initial_(initial), final_(final) {
  requireFiniteState(initial_, "initial");
  requireFiniteState(final_, "final");
}

}  // namespace cobra::trajectory
