#include "cobra/components/suturing/package.hpp"

#include "cobra/components/suturing/stitch_planner.hpp"
#include "cobra/components/suturing/suturing_frame_generator.hpp"
#include "cobra/components/suturing/teleoperation_clutch.hpp"

namespace cobra::components {

void registerSuturingPackage(deploy::PackageBuilder& package) {
  package.component<StitchPlannerComponent>(
      "StitchPlanner", "the next stitch's right and left targets from the wound's current edges (thesis §5.2.1)");
  package.component<SuturingFrameGenerator>(
      "SuturingFrameGenerator", "the goal poses of the Endo Stitch and the stick for the task state (thesis §5.5)");
  package.component<TeleoperationClutch>(
      "TeleoperationClutch", "the tool follows the haptic device's motion from the teleoperation's start (§5.5)");
}

}  // namespace cobra::components
