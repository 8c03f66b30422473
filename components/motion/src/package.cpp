#include "cobra/components/motion/package.hpp"

#include "cobra/components/motion/cartesian_trajectory_generator.hpp"

namespace cobra::components {

void registerMotionPackage(deploy::PackageBuilder& package) {
  package.component<CartesianTrajectoryGenerator>(
      "CartesianTrajectoryGenerator", "synchronised multi-arm Cartesian set-points along a planned path (thesis §4.5.2)");
}

}  // namespace cobra::components
