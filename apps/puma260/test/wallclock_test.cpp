// The Puma 260 task on the wall clock (`cobra run apps/puma260 --realtime`): the deployment's
// schedule, the MuJoCo world included, run by the real-time executor instead of the lockstep clock,
// with the lockstep run's acceptance (puma260_task_expectations.hpp: phases A-H, the ride on the
// surface as the admittance predicts, Fig. 6.7's path back within 1 mm, the tank). Label wallclock.

#include <gtest/gtest.h>

#include <cstdio>

#include "puma260_task_expectations.hpp"

namespace cobra::run::puma260 {
namespace {

TEST(Puma260OnTheWallClock, TheClosedFormVariantPassesTheLockstepChecks) {
  RunOptions o = options("closed_form", "closed_form_wall");
  o.realtime = true;
  const RunResult r = runApp(o);
  const ExecutorFigures& e = r.executor;
  std::printf("wall clock: %s in %.3f s; %s\n", toString(r.outcome), r.duration, executorLine(e).c_str());
  expectTheTask(r, o);
  ASSERT_TRUE(e.ran);
  EXPECT_EQ(count(r, "Executor: e_deadline_safe_stop"), 0u);
  EXPECT_EQ(count(r, "e_ik_discontinuity"), 0u);
}

}  // namespace
}  // namespace cobra::run::puma260
