// The "cobra_puncturing" package: loaded by name (packages_list = { ..., "cobra_puncturing" }) from
// libcobra_puncturing.so, beside the tool's packages.
#include <cstdint>

#include "cobra/components/puncturing/frame_generator.hpp"
#include "cobra/components/puncturing/procedure_planner.hpp"
#include "cobra/components/puncturing/scripted_surgeon.hpp"
#include "cobra/deploy/package_registry.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  using namespace cobra::components;
  package
      .component<PuncturingFrameGenerator>(
          "PuncturingFrameGenerator",
          "the goal poses of needle and probe for the current puncturing task state (thesis §4.5.5)")
      .component<PuncturingMotionPlanner>(
          "PuncturingMotionPlanner",
          "the MotionPlanner with verifyProcedure(): every motion of the procedure verified before the first")
      .component<ScriptedSurgeon>("ScriptedSurgeon",
                                  "the surgeon's console in simulation: a surgeon script played against the task "
                                  "charts, and say(event)");
}
