// The puncturing task on the wall clock (`cobra run apps/puncturing --realtime`): the deployment's
// schedule run by the real-time executor (core/realtime_executor.hpp) instead of the lockstep
// clock. It must do what the lockstep run does, up to timing: the same procedure with the same
// acceptance (procedure_expectations.hpp), the needles placed where the lockstep run places them,
// no deadline-miss policy triggered, and every event stamped in run time. Label wallclock: minutes
// of wall time.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "cobra/run/runner.hpp"
#include "procedure_expectations.hpp"

namespace cobra::run {
namespace {

using namespace testing;

/// s: the stamp an event carries ("... at 12.345 s"), NaN when it has none.
double stampOf(const std::string& event) {
  const auto at = event.rfind(" at ");
  return at == std::string::npos ? NAN : std::strtod(event.c_str() + at + 4, nullptr);
}

TEST(PuncturingOnTheWallClock, TheNominalProcedureDoesWhatTheLockstepRunDoes) {
  const RunResult lockstep = runApp(options("two_needles"));
  ASSERT_TRUE(lockstep.completed()) << lockstep.reason;
  RunOptions o = options("two_needles");
  o.realtime = true;
  o.time_limit = 300.0;  // s of run time; the procedure takes about 105 s
  const RunResult r = runApp(o);
  const ExecutorFigures& e = r.executor;
  std::printf("wall clock: %s in %.3f s; %s\n", toString(r.outcome), r.duration, executorLine(e).c_str());
  ASSERT_TRUE(r.completed()) << r.reason;
  ASSERT_TRUE(e.ran) << "the executor ran the deployment";
  EXPECT_GT(e.ticks, 100000u);
  EXPECT_EQ(count(r, "Executor: e_deadline_safe_stop"), 0u);
  expectPlaced(r, 2);
  expectFaithful(r, 2.0);  // tracking <= 2 mm and 1 deg, no IK refusal, clearance from the planner's first answer
  expectNoCommandJump(r);
  EXPECT_EQ(count(r, "needle > root.WaitReaction"), 0u);
  EXPECT_EQ(count(r, "us > root.WaitReaction"), 0u);
  const SummaryValue& wall = r.value("placement error per needle");
  const SummaryValue& simulated = lockstep.value("placement error per needle");
  ASSERT_EQ(wall.values.size(), simulated.values.size());
  for (std::size_t i = 0; i < wall.values.size(); ++i) {
    std::printf("needle %zu placed %.3f mm from its target (lockstep %.3f mm)\n", i + 1, wall.values[i], simulated.values[i]);
    EXPECT_LE(wall.values[i], 1.0) << "needle " << i + 1 << " (mm)";
    EXPECT_NEAR(wall.values[i], simulated.values[i], 0.2) << "needle " << i + 1 << " (mm) against the lockstep run";
  }
  // Every event's own stamp is run time: what the run observed it at, within the observer's steps.
  std::size_t stamped = 0;
  for (const report::EventRecord& event : r.events) {
    const double stamp = stampOf(event.event);
    if (std::isnan(stamp)) continue;
    ++stamped;
    EXPECT_NEAR(stamp, event.time, 0.1) << event.source << ": " << event.event;
  }
  EXPECT_GT(stamped, 50u);
}

}  // namespace
}  // namespace cobra::run
