// Setups vary (issue 15): a phantom is never registered exactly where the scenario says. Each
// test runs the two-needle procedure with the abdomen registered off its nominal pose by a seeded
// random shift and turn, and expects the outcome stated below for its seed. Where a registration
// brings the first probe pose, and the UR5's forearm with it, under the needle robot's usual
// needle change pose, the needle robot waits at another one that leaves the probe's approach free
// (state_table.txt: MakeRoomForProbe, MoveToNeedleChange), so no seed stops there any more.
//
// Six of the eight seeds cannot insert the second needle, and stop safely before it moves: at the
// second needle's target the I-SUR's micro arm (its upper arm or yaw link) comes within the 5 mm
// threshold of the UR5's forearm or first wrist link, which holds the probe at its planned pose
// (us_plan.txt: the pose is fixed per needle, 35 mm beyond the needle's tip, and turns with the
// abdomen while both robot bases stay). Nothing in the state table changes where either arm is at
// that moment (the needle's roll about its axis turns its last joint only), so with this probe
// plan these registrations are infeasible: the planner refuses the second needle's approach,
// whose follow-on check walks the insertion to the target (then_needle), names the goal and the
// pair, and the run ends in the safe stop after the reaction's retry. Before this check, and
// before the clearance was measured during the insertion, these runs "completed" with the two
// arms 4.3-4.5 mm apart for seeds 1, 3 and 6, and touching (0 mm) for seeds 2, 4 and 7. A probe plan with alternative poses
// per needle, chosen at plan time as the needle change poses are, would lift this (not done).
// One procedure per seed (about 100 s simulated, 5-15 s here): CTest label `procedure_slow`.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "cobra/run/runner.hpp"
#include "cobra/test_support/test_support.hpp"
#include "procedure_expectations.hpp"

namespace cobra::run {
namespace {

using namespace testing;

constexpr double kMaxShift = 0.03;  // m, along x and y of the task frame (the phantom stays on the table)
constexpr double kMaxTurn = 0.5;    // rad (29 deg) about the vertical, added to the scenario's yaw

/// A registration: the scenario's abdomen moved by (dx, dy) m and turned by dyaw rad.
struct Registration {
  unsigned seed;
  double dx, dy, dyaw;
};

Registration draw(unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> shift(-kMaxShift, kMaxShift), turn(-kMaxTurn, kMaxTurn);
  const double dx = shift(random), dy = shift(random);
  return {seed, dx, dy, turn(random)};
}

/// A copy of scenario `name` whose preoperative `abdomen` line is moved by `r`; every file that
/// places the phantom (the Patient, the planner's phantom, the Frame Generators, the monitor's
/// forbidden regions) reads that line, so the whole setup moves with it.
std::filesystem::path registered(const std::string& name, const Registration& r) {
  const std::filesystem::path from = kApp / "scenarios" / name;
  const std::filesystem::path to =
      std::filesystem::temp_directory_path() / ("cobra_registration_" + name + "_" + std::to_string(r.seed));
  std::filesystem::remove_all(to);
  std::filesystem::create_directories(to);
  for (const auto& file : std::filesystem::directory_iterator(from))
    std::filesystem::copy(file.path(), to / file.path().filename());
  std::ifstream in(from / "preoperative.txt");
  std::ostringstream out;
  bool moved = false;
  for (std::string line; std::getline(in, line);) {
    double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
    if (std::sscanf(line.c_str(), "abdomen xyz=%lf,%lf,%lf rpy=%lf,%lf,%lf", &x, &y, &z, &roll, &pitch, &yaw) == 6) {
      char text[200];
      std::snprintf(text, sizeof text, "abdomen xyz=%.6f,%.6f,%.6f rpy=%.6f,%.6f,%.6f  # seed %u", x + r.dx, y + r.dy, z,
                    roll, pitch, yaw + r.dyaw, r.seed);
      line = text;
      moved = true;
    }
    out << line << "\n";
  }
  EXPECT_TRUE(moved) << from / "preoperative.txt" << " has no `abdomen xyz=X,Y,Z rpy=R,P,Y` line";
  std::ofstream(to / "preoperative.txt") << out.str();
  return to;
}

/// The figures of a run, for the log (placement, worst tracking, clearance, contacts).
void say(const Registration& r, const RunResult& result) {
  const SummaryValue& placed = result.value("placement error per needle");
  std::printf("seed %u (dx %+.4f m, dy %+.4f m, dyaw %+.3f rad): %s at %.1f s; placement %s; tracking %.2f mm / "
              "%.2f deg (needle), %.2f mm / %.2f deg (probe); clearance %.2f mm; contacts %s %.2f mm, %s %.2f mm\n",
              r.seed, r.dx, r.dy, r.dyaw, toString(result.outcome), result.duration, placed.text.c_str(),
              result.tracking[kNeedle].position_mm.value, result.tracking[kNeedle].orientation_deg.value,
              result.tracking[kProbe].position_mm.value, result.tracking[kProbe].orientation_deg.value,
              1000.0 * result.clearance.worst, result.clearance.contacts.at(0).first.c_str(),
              1000.0 * result.clearance.contacts.at(0).second, result.clearance.contacts.at(1).first.c_str(),
              1000.0 * result.clearance.contacts.at(1).second);
}

/// A seed and whether its registration lets the procedure complete (see the top of this file).
struct Case {
  unsigned seed;
  bool completes;
};

class RegisteredOffNominal : public ::testing::TestWithParam<Case> {};

TEST_P(RegisteredOffNominal, TheProcedureCompletesFaithfullyOrStopsBeforeTheInfeasibleNeedle) {
  const Registration r = draw(GetParam().seed);
  RecordProperty("registration", "dx " + std::to_string(r.dx) + " m, dy " + std::to_string(r.dy) + " m, dyaw " +
                                     std::to_string(r.dyaw) + " rad");
  RunOptions o = options(registered("two_needles", r));
  const RunResult result = runApp(o);
  SCOPED_TRACE("seed " + std::to_string(r.seed) + ": abdomen moved by (" + std::to_string(r.dx) + ", " +
               std::to_string(r.dy) + ") m, turned by " + std::to_string(r.dyaw) + " rad");
  EXPECT_LT(result.duration, o.time_limit);
  say(r, result);
  if (GetParam().completes) {
    ASSERT_TRUE(result.completed()) << toString(result.outcome) << " at " << result.duration << " s: " << result.reason;
    expectPlaced(result, 2);
    expectFaithful(result);
    return;
  }
  ASSERT_EQ(result.outcome, Outcome::SafeStop) << "at " << result.duration << " s: " << result.reason;
  RecordProperty("safe_stop", result.reason);
  // The first needle placed; the second refused at plan time, naming its goal and the pair.
  expectPlaced(result, 1);
  EXPECT_CONTAINS(result.reason, "needle chart stopped safely in root.InsertingNeedles.MoveToSkin.Approach: "
                                 "NeedlePlanner: e_plan_failed");
  EXPECT_CONTAINS(result.reason, "the same failure again after the reaction to the first");
  EXPECT_CONTAINS(result.reason, "invalid goal: the straight motion after the goal, to (");
  EXPECT_CONTAINS(result.reason, "cannot be made: too close: micro/ur5 at 0.00");
  // Stopped before anything went wrong: no swing, no contact the whole run long.
  expectTracked(result);
  expectClear(result);
}

// Eight seeds: shifts up to 3 cm along x and y, turns up to 0.5 rad about the vertical.
INSTANTIATE_TEST_SUITE_P(EightSeeds, RegisteredOffNominal,
                         ::testing::Values(Case{1, false}, Case{2, false}, Case{3, false}, Case{4, false}, Case{5, true},
                                           Case{6, false}, Case{7, false}, Case{8, true}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return "seed" + std::to_string(param.param.seed) +
                                  (param.param.completes ? "_completes" : "_stops");
                         });

}  // namespace
}  // namespace cobra::run
