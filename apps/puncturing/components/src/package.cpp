#include "cobra/components/puncturing/package.hpp"

#include "cobra/components/puncturing/frame_generator.hpp"
#include "cobra/components/puncturing/scripted_surgeon.hpp"

namespace cobra::components {

void registerPuncturingPackage(deploy::PackageBuilder& package) {
  package
      .component<PuncturingFrameGenerator>(
          "PuncturingFrameGenerator",
          "the goal poses of needle and probe for the current puncturing task state (thesis §4.5.5)")
      .component<ScriptedSurgeon>("ScriptedSurgeon",
                                  "the surgeon's console in simulation: a surgeon script played against the task "
                                  "charts, and say(event)");
}

}  // namespace cobra::components
