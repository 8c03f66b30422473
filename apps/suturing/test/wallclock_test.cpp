// The suturing task on the wall clock (`cobra run apps/suturing --realtime`): the deployment's
// schedule run by the real-time executor instead of the lockstep clock, with the lockstep run's
// acceptance (procedure_expectations.hpp): every stitch applied and closed, tracking, no IK
// refusal, the threads pulling on the stick, the tanks. Label wallclock: minutes of wall time.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "cobra/run/runner.hpp"
#include "procedure_expectations.hpp"

namespace cobra::run {
namespace {

using namespace suturing_testing;

TEST(SuturingOnTheWallClock, TheStraightCutIsClosedAsInLockstep) {
  const RunResult lockstep = runApp(options("straight_cut"));
  expectSutured(lockstep, 4);
  RunOptions o = options("straight_cut");
  o.realtime = true;
  o.report_folder = std::filesystem::temp_directory_path() / ("cobra_suturing_wall_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  const ExecutorFigures& e = r.executor;
  std::printf("wall clock: %s in %.3f s; %s\n", toString(r.outcome), r.duration, executorLine(e).c_str());
  expectSutured(r, 4);
  ASSERT_TRUE(e.ran);
  EXPECT_EQ(count(r, "Executor: e_deadline_safe_stop"), 0u);
  EXPECT_EQ(count(r, "suture > root.WaitReaction"), 0u);
  EXPECT_EQ(count(r, "Patient: e_thread_broken"), 0u);
  expectCaughtOnlyByTheHookingMotion(r);
  const Signals signals(o.report_folder);
  expectTheThreadsPullOnTheStick(r, signals);
  expectTheTanksHoldTheWorkAgainstTheThread(r, signals);
  const SummaryValue& wall = r.value("gap at the stitches after each stitch");
  const SummaryValue& simulated = lockstep.value("gap at the stitches after each stitch");
  for (std::size_t i = 0; i < wall.values.size() && i < simulated.values.size(); ++i)
    std::printf("stitch %zu: gap %.3f mm (lockstep %.3f mm)\n", i + 1, wall.values[i], simulated.values[i]);
  std::filesystem::remove_all(o.report_folder);
}

}  // namespace
}  // namespace cobra::run
