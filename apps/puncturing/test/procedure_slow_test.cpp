// Setups vary: a phantom is never registered exactly where the scenario says. Each
// test runs the two-needle procedure with the abdomen registered off its nominal pose by a seeded
// random shift and turn (seeds 1-8, and 54, below): the procedure completes with the fidelity
// of the procedure acceptance (both needles placed within 2 mm, tracking within 2 mm and 1 deg,
// no IK discontinuity, the measured clearance above the planner's threshold the whole run long, the
// needle's insertion included). What makes the registrations feasible (apps/puncturing/README.md,
// "Setups vary"): the needle robot waits at the first needle change pose that leaves room for
// the probe's next approach (state_table.txt: MakeRoomForProbe, MoveToNeedleChange), each
// needle's approach is verified with the insertion that follows it (then_needle), and the probe
// plan stands 45 mm beyond each needle's tip (tools/probe_plan.py; at 35 mm the I-SUR's micro
// arm came within 5 mm of the UR5 at the second needle's target in six of these eight seeds,
// touching it in three). One procedure per seed (about 160 s simulated, 5-15 s here): CTest
// label `procedure_slow`.

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "cobra/run/runner.hpp"
#include "procedure_expectations.hpp"
#include "registration.hpp"

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

/// The scenario with its abdomen moved by (dx, dy) m and turned by dyaw rad about the vertical.
std::filesystem::path registered(const std::string& name, const Registration& r) {
  return testing::registered(name, "seed_" + std::to_string(r.seed), [&](const KDL::Frame& a) {
    return KDL::Frame(KDL::Rotation::RotZ(r.dyaw) * a.M, a.p + KDL::Vector(r.dx, r.dy, 0.0));
  });
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

class RegisteredOffNominal : public ::testing::TestWithParam<unsigned> {};

TEST_P(RegisteredOffNominal, TheProcedureCompletesFaithfully) {
  const Registration r = draw(GetParam());
  RecordProperty("registration", "dx " + std::to_string(r.dx) + " m, dy " + std::to_string(r.dy) + " m, dyaw " +
                                     std::to_string(r.dyaw) + " rad");
  RunOptions o = options(registered("two_needles", r));
  const RunResult result = runApp(o);
  SCOPED_TRACE("seed " + std::to_string(r.seed) + ": abdomen moved by (" + std::to_string(r.dx) + ", " +
               std::to_string(r.dy) + ") m, turned by " + std::to_string(r.dyaw) + " rad");
  say(r, result);
  ASSERT_TRUE(result.completed()) << toString(result.outcome) << " at " << result.duration << " s: " << result.reason;
  EXPECT_LT(result.duration, o.time_limit);
  expectPlaced(result, 2);
  expectFaithful(result);
}

// Seeds 1-8: shifts up to 3 cm along x and y, turns up to 0.5 rad about the vertical. With the
// probe plan 45 mm beyond the tips the usual needle change pose leaves room for the probe in all
// of them; seed 54 is the one of seeds 1-100 where it does not (the probe's first approach would
// bring the UR5's forearm within 5 mm of the waiting needle: the planner's room check, run over
// the 100 registrations), so the needle robot makes room at needle_change_aside, then waits above
// the first needle's entry (hold) while the probe moves to the second pose.
INSTANTIATE_TEST_SUITE_P(Seeds, RegisteredOffNominal, ::testing::Values(1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 54u));

}  // namespace
}  // namespace cobra::run
