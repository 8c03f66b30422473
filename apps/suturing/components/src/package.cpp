// The "cobra_suturing" package: loaded by name (packages_list = { ..., "cobra_suturing" }) from
// libcobra_suturing.so, beside the tool's packages.
#include <cstdint>

#include "cobra/components/suturing/rest_monitor.hpp"
#include "cobra/components/suturing/stitch_planner.hpp"
#include "cobra/components/suturing/suturing_frame_generator.hpp"
#include "cobra/deploy/package_registry.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  using namespace cobra::components;
  package.component<StitchPlannerComponent>(
      "StitchPlanner", "the next stitch's right and left targets from the wound's current edges (thesis §5.2.1)");
  package.component<SuturingFrameGenerator>(
      "SuturingFrameGenerator", "the goal poses of the Endo Stitch and the stick for the task state (thesis §5.5)");
  package.component<RestMonitor>("RestMonitor",
                                 "whether the Endo Stitch and the stick are at rest (the chart's end of the procedure)");
}
