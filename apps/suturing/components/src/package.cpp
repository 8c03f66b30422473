#include "cobra/components/suturing/package.hpp"

#include "cobra/components/suturing/stitch_planner.hpp"

namespace cobra::components {

void registerSuturingPackage(deploy::PackageBuilder& package) {
  package.component<StitchPlannerComponent>(
      "StitchPlanner", "the next stitch's right and left targets from the wound's current edges (thesis §5.2.1)");
}

}  // namespace cobra::components
