#include "cobra/components/planning/package.hpp"

#include "cobra/components/planning/motion_planner_component.hpp"
#include "cobra/components/planning/state_validator_component.hpp"

namespace cobra::components {

void registerPlanningPackage(deploy::PackageBuilder& package) {
  package
      .component<MotionPlannerComponent>("MotionPlanner",
                                         "collision-free needle/probe paths, OMPL SE(3)xSE(3) + FCL (thesis §4.5.1)")
      .component<StateValidatorComponent>(
          "StateValidator", "passes valid teleoperation set-points on, else the last valid (thesis §5.4.2)");
}

}  // namespace cobra::components
