#include "cobra/components/motion/package.hpp"

#include "cobra/components/motion/cartesian_trajectory_generator.hpp"
#include "cobra/components/motion/equivalent_wrench.hpp"
#include "cobra/components/motion/kinematics_solver_component.hpp"
#include "cobra/components/motion/waypoint_path.hpp"

namespace cobra::components {

void registerMotionPackage(deploy::PackageBuilder& package) {
  package.component<CartesianTrajectoryGenerator>(
      "CartesianTrajectoryGenerator", "synchronised multi-arm Cartesian set-points along a planned path (thesis §4.5.2)")
      .component<EquivalentWrench>("EquivalentWrench", "a wrench moved to another application point and/or frame (thesis §6.2.3)")
      .component<KinematicsSolverComponent>("KinematicsSolver",
                                            "forward/inverse kinematics, KDL or closed form by a property (thesis §6.2.4)")
      .component<KdlKinematicsSolver>("KdlKinematicsSolver", "KinematicsSolver with KDL's LMA solver by default")
      .component<ClosedFormKinematicsSolver>("ClosedFormKinematicsSolver",
                                             "KinematicsSolver with the robot's closed form by default")
      .component<WaypointPath>("WaypointPath",
                               "a fixed Cartesian path (property waypoints) sent from the tool's measured pose on request");
}

}  // namespace cobra::components
