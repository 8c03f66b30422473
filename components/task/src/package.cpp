#include "cobra/components/task/package.hpp"

#include "cobra/components/task/state_table_frame_generator.hpp"

namespace cobra::components {

void registerTaskPackage(deploy::PackageBuilder& package) {
  package.component<StateTableFrameGenerator>(
      "StateTableFrameGenerator",
      "the goal poses of two arms (arm1, arm2) for the task state, from a state table of fixed poses and holds "
      "(thesis §4.5.5)");
}

}  // namespace cobra::components
