#pragma once
// What the procedure tests (procedure_test.cpp, procedure_slow_test.cpp) expect of a run: the
// scenario's options, the needles placed, the log's order, and the fidelity of issue 15.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cobra/puncturing/procedure.hpp"

namespace cobra::puncturing::testing {

inline const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "apps" / "puncturing";

/// The acceptance figures of issue 15, during autonomous motions (fidelity.hpp).
constexpr double kMaxTrackingMm = kAcceptedTrackingMm;
constexpr double kMaxTrackingDeg = kAcceptedTrackingDeg;

inline ProcedureOptions options(const std::filesystem::path& scenario) {
  ProcedureOptions o;
  o.deployment_file = kApp / "puncturing.lua";
  o.scenario = scenario.is_absolute() ? scenario : kApp / "scenarios" / scenario;
  o.time_limit = 400.0;  // s simulated; a nominal two-needle procedure takes about 105 s
  return o;
}

/// How many needles the scenario's cryo_plan.txt plans.
inline std::size_t plannedNeedles(const std::filesystem::path& scenario) {
  std::ifstream in(scenario / "cryo_plan.txt");
  std::size_t needles = 0;
  for (std::string line; std::getline(in, line);) needles += line.rfind("needle ", 0) == 0;
  return needles;
}

inline void expectPlaced(const ProcedureResult& r, std::size_t needles) {
  ASSERT_EQ(r.placements.size(), needles);
  for (const NeedlePlacement& p : r.placements) EXPECT_LE(p.error_mm, 2.0) << "needle " << p.needle + 1;
}

/// The robots followed their commands without swinging: tracking within the acceptance figures.
inline void expectTracked(const ProcedureResult& r) {
  for (const TrackingFigures* robot : {&r.fidelity.needle, &r.fidelity.probe}) {
    EXPECT_LE(robot->position_mm.value, kMaxTrackingMm)
        << robot->robot << ": worst tracking error " << robot->position_mm.value << " mm at " << robot->position_mm.at
        << " s in " << robot->position_mm.state << "; " << robot->seconds_above_5mm << " s above 5 mm";
    EXPECT_LE(robot->orientation_deg.value, kMaxTrackingDeg)
        << robot->robot << ": worst orientation error " << robot->orientation_deg.value << " deg at "
        << robot->orientation_deg.at << " s in " << robot->orientation_deg.state;
    EXPECT_EQ(robot->joint_jumps, 0) << robot->robot << ": joints at their velocity limit:\n" << robot->joint_jump_log;
  }
}

/// The measured state's clearance stayed above the planner's threshold outside the allowed
/// contacts, the measured poses reachable for the planner's robot models.
inline void expectClear(const ProcedureResult& r) {
  const ClearanceFigures& c = r.fidelity.clearance;
  std::string breaches;
  for (const ClearanceFigures::Breach& b : c.breaches)
    breaches += "\n  " + b.pair + ": " + std::to_string(b.seconds) + " s, closest " + std::to_string(1000.0 * b.worst) +
                " mm at " + std::to_string(b.at) + " s (" + b.state + ")";
  EXPECT_GT(c.worst, c.threshold) << "clearance " << 1000.0 * c.worst << " mm (threshold " << 1000.0 * c.threshold
                                  << " mm) at " << c.worst_at << " s between " << c.worst_pair << ", " << c.worst_state
                                  << "; " << c.seconds_below << " s at or under the threshold; the pairs:" << breaches;
  EXPECT_EQ(c.unreachable, 0) << "samples of the measured state the planner's robot models cannot reach";
}

/// Issue 15's acceptance: tracking, no IK discontinuity, the measured state's clearance at least
/// the planner's threshold outside the allowed contacts.
inline void expectFaithful(const ProcedureResult& r) {
  for (const TrackingFigures* robot : {&r.fidelity.needle, &r.fidelity.probe})
    EXPECT_GT(robot->seconds_sampled, 0.0) << robot->robot << ": no autonomous sample";
  expectTracked(r);
  std::string events;
  for (const std::string& e : r.fidelity.ik_discontinuities) events += "\n  " + e;
  EXPECT_TRUE(r.fidelity.ik_discontinuities.empty()) << "e_ik_discontinuity events:" << events;
  expectClear(r);
}

/// Asserts that `lines` appear in the run's log in this order (other lines may come between).
inline void expectInOrder(const ProcedureResult& r, const std::vector<std::string>& lines) {
  std::size_t at = 0;
  std::string previous = "(start)";
  for (const std::string& line : lines) {
    std::size_t found = at;
    while (found < r.log.size() && r.log[found] != line) ++found;
    if (found == r.log.size()) {
      std::string tail;
      for (std::size_t i = at; i < r.log.size() && i < at + 40; ++i) tail += "\n  " + r.log[i];
      FAIL() << "missing, in order: " << line << "; after " << previous << " (line " << at << " of " << r.log.size()
             << " of the log), which is followed by:" << tail;
    }
    at = found + 1;
    previous = line;
  }
}

inline std::size_t count(const ProcedureResult& r, const std::string& line) {
  return static_cast<std::size_t>(std::count(r.log.begin(), r.log.end(), line));
}

}  // namespace cobra::puncturing::testing
