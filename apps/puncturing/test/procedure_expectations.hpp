#pragma once
// What the procedure tests (procedure_test.cpp, procedure_slow_test.cpp) expect of a run of
// apps/puncturing through the runner's API (cobra/run/runner.hpp): the scenario's options, the
// needles placed, the log's order, and the fidelity (the robot did what it was told) as the app's
// `run` table declares it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "cobra/run/runner.hpp"

namespace cobra::run::testing {

inline const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "apps" / "puncturing";
inline const std::filesystem::path kFaults = kApp / "test" / "faults";

/// The procedure acceptance's tracking figures, during autonomous motions.
constexpr double kMaxTrackingMm = 2.0;
constexpr double kMaxTrackingDeg = 1.0;

/// The tracked tools, in the order of the app's run.tracking.
constexpr std::size_t kNeedle = 0, kProbe = 1;

inline RunOptions options(const std::filesystem::path& scenario) {
  RunOptions o;
  o.app = kApp;
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

/// Every needle placed within 2 mm of its target (the tip during the freeze).
inline void expectPlaced(const RunResult& r, std::size_t needles) {
  const SummaryValue& placed = r.value("placement error per needle");
  ASSERT_EQ(placed.values.size(), needles) << placed.text;
  for (std::size_t i = 0; i < placed.values.size(); ++i) EXPECT_LE(placed.values[i], 2.0) << "needle " << i + 1;
}

/// The robots followed their commands without swinging: tracking within the acceptance figures.
inline void expectTracked(const RunResult& r) {
  ASSERT_EQ(r.tracking.size(), 2u);
  for (const TrackingFigures& robot : r.tracking) {
    EXPECT_LE(robot.position_mm.value, kMaxTrackingMm)
        << robot.robot << ": worst tracking error " << robot.position_mm.value << " mm at " << robot.position_mm.at
        << " s in " << robot.position_mm.state << "; " << robot.seconds_above_5mm << " s above 5 mm";
    EXPECT_LE(robot.orientation_deg.value, kMaxTrackingDeg)
        << robot.robot << ": worst orientation error " << robot.orientation_deg.value << " deg at "
        << robot.orientation_deg.at << " s in " << robot.orientation_deg.state;
    EXPECT_EQ(robot.joint_jumps, 0) << robot.robot << ": joints at their velocity limit:\n" << robot.joint_jump_log;
  }
}

/// The measured state's clearance (the needle planner's minDistance, the declared contacts left
/// out: the probe on the skin, the needle in the tissue) stayed above the planner's threshold the
/// whole run long, the needle's insertion included (no pause), every sample measurable.
/// `unsampled` (s): how long the run may go before the first sample. On the lockstep clock the
/// planner measures from the first step; on the wall clock it measures on its own thread (an
/// own-pace activity), whose first answer comes after its first wake-up, up to a second late on a
/// loaded machine.
inline void expectClear(const RunResult& r, double unsampled = 0.02) {
  const ClearanceFigures& c = r.clearance;
  EXPECT_GT(c.threshold, 0.0);
  // One sample per 1 ms step from the first measured pose (within the first 10 ms) to the end.
  EXPECT_GE(c.seconds_sampled, r.duration - unsampled) << "s of clearance samples in a run of " << r.duration << " s";
  EXPECT_GT(c.worst, c.threshold) << "clearance " << 1000.0 * c.worst << " mm (threshold " << 1000.0 * c.threshold
                                  << " mm) at " << c.worst_at << " s, " << c.worst_state << "; " << c.seconds_below
                                  << " s at or under the threshold";
  EXPECT_EQ(c.unreachable, 0) << "samples of the measured state the planner's robot models cannot reach";
}

/// The needle robot's command never jumped between two 1 ms steps (switches included).
inline void expectNoCommandJump(const RunResult& r) {
  ASSERT_EQ(r.tracking.size(), 2u);
  EXPECT_LT(r.tracking[kNeedle].max_command_step, 1e-3) << "at " << r.tracking[kNeedle].max_command_step_at << " s";
}

/// The procedure acceptance: tracking, no IK discontinuity, the measured state's clearance above the
/// planner's threshold outside the allowed contacts.
inline void expectFaithful(const RunResult& r, double unsampled = 0.02) {
  for (const TrackingFigures& robot : r.tracking)
    EXPECT_GT(robot.seconds_sampled, 0.0) << robot.robot << ": no autonomous sample";
  expectTracked(r);
  std::string events;
  for (const report::EventRecord& e : r.events)
    if (e.event.rfind("e_ik_discontinuity", 0) == 0)
      events += "\n  " + std::to_string(e.time) + " s " + e.source + " (" + e.state + ")";
  EXPECT_TRUE(events.empty()) << "e_ik_discontinuity events:" << events;
  EXPECT_GT(r.clearance.seconds_sampled, 10.0);
  expectClear(r, unsampled);
  // The declared contacts were made (each reported apart, 0: touching or inside).
  ASSERT_EQ(r.clearance.contacts.size(), 2u);
  for (const auto& [name, distance] : r.clearance.contacts) EXPECT_EQ(distance, 0.0) << name;
}

/// Asserts that `lines` appear in the run's log in this order (other lines may come between).
inline void expectInOrder(const RunResult& r, const std::vector<std::string>& lines) {
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

inline std::size_t count(const RunResult& r, const std::string& line) {
  return static_cast<std::size_t>(std::count(r.log.begin(), r.log.end(), line));
}

/// The rows of a run folder's signals.csv from t >= `from` s, and the index of the first column
/// whose header starts with `column` (-1: none).
inline std::vector<std::vector<double>> signalRows(const std::filesystem::path& signals, const std::string& column,
                                                   double from, int& index) {
  std::ifstream in(signals);
  std::string header;
  std::getline(in, header);
  index = -1;
  int i = 0;
  std::istringstream cells(header);
  for (std::string cell; std::getline(cells, cell, ','); ++i)
    if (index < 0 && cell.rfind(column, 0) == 0) index = i;
  std::vector<std::vector<double>> rows;
  for (std::string row; std::getline(in, row);) {
    std::vector<double> v;
    std::istringstream values(row);
    for (std::string cell; std::getline(values, cell, ',');)
      v.push_back(cell.empty() ? std::numeric_limits<double>::quiet_NaN() : std::stod(cell));
    if (!v.empty() && v[0] >= from && index >= 0 && static_cast<int>(v.size()) > index + 2) rows.push_back(std::move(v));
  }
  return rows;
}

/// The smallest value of `column` (e.g. "NeedleAdmittance.tankEnergy") in signals.csv; NaN when
/// there is no such column.
inline double columnMinimum(const std::filesystem::path& signals, const std::string& column) {
  int index = -1;
  const auto rows = signalRows(signals, column + " ", 0.0, index);
  if (index < 0) return std::numeric_limits<double>::quiet_NaN();
  double minimum = std::numeric_limits<double>::infinity();
  for (const auto& v : rows)
    if (!std::isnan(v[index])) minimum = std::min(minimum, v[index]);
  return minimum;
}

/// The energy tanks of both variable admittances never emptied (passivity kept all along), from a
/// run folder's signals.csv.
inline void expectTanksHeld(const std::filesystem::path& report_folder) {
  EXPECT_GT(columnMinimum(report_folder / "signals.csv", "NeedleAdmittance.tankEnergy"), 0.0);
  EXPECT_GT(columnMinimum(report_folder / "signals.csv", "ProbeAdmittance.tankEnergy"), 0.0);
}

}  // namespace cobra::run::testing
