#pragma once
// What the suturing procedure tests (procedure_test.cpp on the lockstep clock, wallclock_test.cpp on
// the wall clock) expect of a run of apps/suturing through the runner's API: the scenario's
// options, the stitches closed, the log's order, the threads' pull and the tanks.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cobra/run/runner.hpp"

namespace cobra::run::suturing_testing {

inline const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "apps" / "suturing";
inline const std::filesystem::path kFaults = kApp / "test" / "faults";
constexpr double kMaxTrackingMm = 2.0;  // the procedure acceptance, during the autonomous motions
constexpr double kMaxTrackingDeg = 1.0;
constexpr double kClosedGapMm = 0.5;    // the scenarios' closed_gap
constexpr double kTankInitialJ = 5.0;   // its tank_initial default
// The contact configuration's translational stiffness on the Endo Stitch (components/control/
// configurations/suturing/contact.lua) and its variable part Kv = K - Kc above the admittance's
// constant_stiffness default (50 N/m): the part the tank pays for.
constexpr double kContactStiffness = 3000.0;                 // N/m
constexpr double kContactVariable = kContactStiffness - 50.0;  // N/m

inline RunOptions options(const std::string& scenario, const std::string& device = "leap") {
  RunOptions o;
  o.app = kApp;
  o.scenario = kApp / "scenarios" / scenario;
  o.time_limit = 300.0;  // s simulated; the default scenario takes about 72 s
  o.before_lua = "teleop_device = '" + device + "'";
  return o;
}

inline RunOptions withFaults(const std::string& faults, const std::string& device = "leap") {
  RunOptions o = options("straight_cut", device);
  o.faults_file = kFaults / faults;
  return o;
}

/// Asserts that `lines` appear in the run's log in this order (other lines may come between).
inline void expectInOrder(const RunResult& r, const std::vector<std::string>& lines) {
  std::size_t at = 0;
  for (const std::string& line : lines) {
    std::size_t found = at;
    while (found < r.log.size() && r.log[found] != line) ++found;
    ASSERT_LT(found, r.log.size()) << "missing, in order: " << line;
    at = found + 1;
  }
}

inline std::size_t count(const RunResult& r, const std::string& line) {
  return static_cast<std::size_t>(std::count(r.log.begin(), r.log.end(), line));
}

/// The run folder's signals.csv: each column by its name without the unit ("Patient.threadTension"
/// for "Patient.threadTension [N]"). A header cell with a comma in its unit is quoted ("[N, N·m]").
struct Signals {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;

  explicit Signals(const std::filesystem::path& folder) {
    std::ifstream in(folder / "signals.csv");
    std::string line;
    std::getline(in, line);
    std::string cell;
    bool quoted = false;
    for (const char c : line + ",") {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) {
        names.push_back(cell.substr(0, cell.find(" [")));
        cell.clear();
      } else cell += c;
    }
    while (std::getline(in, line)) {
      std::stringstream row(line);
      std::vector<double>& values = rows.emplace_back();
      // An empty cell: the port had no data yet (on the wall clock a recording may begin before a
      // port's first sample); strtod, not stod: a subnormal value is a number, not an error.
      for (std::string number; std::getline(row, number, ',');)
        values.push_back(number.empty() ? std::numeric_limits<double>::quiet_NaN() : std::strtod(number.c_str(), nullptr));
    }
  }
  std::size_t column(const std::string& name) const {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) throw std::out_of_range("no column " + name + " in signals.csv");
    return static_cast<std::size_t>(it - names.begin());
  }
  double minimum(const std::string& name) const {
    const std::size_t c = column(name);
    double lowest = std::numeric_limits<double>::infinity();
    for (const auto& row : rows) lowest = std::min(lowest, row[c]);
    return lowest;
  }
  /// The norm of a KDL.Wrench column's force (N) in `row`.
  double force(const std::vector<double>& row, const std::string& wrench) const {
    const std::size_t x = column(wrench + ".fx");
    return std::sqrt(row[x] * row[x] + row[x + 1] * row[x + 1] + row[x + 2] * row[x + 2]);
  }
};

/// Both arms followed their commands during the autonomous motions (sampled over more than
/// `seconds` s each): within the procedure's acceptance, no joint jump.
inline void expectTracked(const RunResult& r, double seconds) {
  ASSERT_EQ(r.tracking.size(), 2u);
  for (const TrackingFigures& arm : r.tracking) {
    EXPECT_GT(arm.seconds_sampled, seconds) << arm.robot;
    EXPECT_LE(arm.position_mm.value, kMaxTrackingMm) << arm.robot << " at " << arm.position_mm.at << " s";
    EXPECT_LE(arm.orientation_deg.value, kMaxTrackingDeg) << arm.robot;
    EXPECT_EQ(arm.joint_jumps, 0) << arm.robot << ":\n" << arm.joint_jump_log;
  }
}

/// Every planned stitch applied (both halves) and closed; the robot followed its commands.
inline void expectSutured(const RunResult& r, std::size_t stitches) {
  ASSERT_TRUE(r.completed()) << r.reason;
  EXPECT_EQ(r.value("half-stitches applied").values.size(), 2 * stitches);  // one sample per event
  EXPECT_EQ(r.value("stitches completed").values.size(), stitches);
  const SummaryValue& gaps = r.value("gap at the stitches after each stitch");
  ASSERT_EQ(gaps.values.size(), stitches) << gaps.text;
  for (std::size_t i = 0; i < gaps.values.size(); ++i) EXPECT_LT(gaps.values[i], kClosedGapMm) << "stitch " << i + 1;
  expectTracked(r, 10.0);
  // No IK refusal during the autonomous motions (in a teleoperation, the robot refusing a sudden
  // jump of the surgeon's set-point is its continuity rule at work).
  for (const report::EventRecord& e : r.events) {
    if (e.state.rfind("root.TeleoperatedMode", 0) == 0) continue;
    EXPECT_NE(e.event.rfind("e_ik_discontinuity", 0), 0u) << e.time << " s " << e.source;
    EXPECT_NE(e.event.rfind("e_ik_failed", 0), 0u) << e.time << " s " << e.source;
  }
}

/// The stick catches the thread in HookThread only (the wound model catches a thread any motion of
/// the stick passes through).
inline void expectCaughtOnlyByTheHookingMotion(const RunResult& r) {
  for (const report::EventRecord& e : r.events) {
    if (e.event.rfind("e_thread_hooked", 0) == 0) {
      EXPECT_EQ(e.state.rfind("root.AutonomousMode.HookThread", 0), 0u) << e.time << " s " << e.state;
    }
  }
}

/// The hooked thread's pull on the stick reaches the left arm's sensor (the robot's measured
/// wrench) as the wound model computes it, and the arm follows its commands through every hook,
/// push and release.
inline void expectTheThreadsPullOnTheStick(const RunResult& r, const Signals& signals) {
  std::vector<double> releases;  // s: when the chart told the stick to let go
  for (const report::EventRecord& e : r.events)
    if (e.event.rfind("e_release_thread", 0) == 0) releases.push_back(e.time);
  EXPECT_EQ(releases.size(), 8u);
  const std::size_t tracking = signals.column("tracking.stick.mm");
  double peak_model = 0.0, peak_sensor = 0.0, worst_tracking = 0.0, hooked_seconds = 0.0;
  double after_release = 0.0;  // N: the sensor's force 0.5 s after each release
  double largest_drop = 0.0;   // N: the pull's largest fall between two records (10 ms)
  double previous = 0.0;
  for (const auto& row : signals.rows) {
    const double pull = signals.force(row, "Patient.stickWrench");
    const double sensed = signals.force(row, "ISUR.measLeftWrench");
    largest_drop = std::max(largest_drop, previous - pull);
    previous = pull;
    const bool released_lately = std::any_of(releases.begin(), releases.end(), [&](double t) {
      return row[0] >= t && row[0] - t <= 1.0;
    });
    if (pull > 0.0) {
      hooked_seconds += 0.01;  // the record period
      peak_model = std::max(peak_model, pull);
      peak_sensor = std::max(peak_sensor, sensed);
    }
    if (pull > 0.0 || released_lately) worst_tracking = std::max(worst_tracking, row[tracking]);
    for (const double t : releases)
      if (std::abs(row[0] - t - 0.5) < 0.005) after_release = std::max(after_release, sensed);
  }
  EXPECT_GT(hooked_seconds, 4.0);  // 8 hooks and pushes of about 1.2 s
  // The peak pull (about 4.9 N: the thread at about 4.6 N bent sharply back round the stick, pushed
  // 10 mm back along the cut from where it rose 8 mm ahead of the stitch): the Nano17's reading,
  // in the tool frame, has the model's magnitude within its resolution and noise (1/160 N a step).
  EXPECT_GT(peak_model, 0.5);
  EXPECT_NEAR(peak_sensor, peak_model, 0.02 + 0.01 * peak_model);
  EXPECT_LT(after_release, 0.02);  // let go: the sensor reads nothing again
  // The thread slides off the stick over the WoundSimulator's release_time (0.2 s): its pull fades
  // (at most 0.47 N per 10 ms) where letting go at once would drop all of it (3.2-4.5 N) in one step.
  EXPECT_LT(largest_drop, 0.25 * peak_model);
  EXPECT_LE(worst_tracking, kMaxTrackingMm);
}

/// The tanks (README.md, "Energy tanks"): each pull against the thread (the contact configuration)
/// stores in the Endo Stitch's tank at least what its variable stiffness Kv holds at the pull's end,
/// Kv x^2 / 2 with x = T / K the admittance's give under the tension T, the dissipated energy only
/// adding to it; the stick's tank gains over each hook and push; neither is ever drawn below its
/// initial energy (every motion starts at the measured pose: the admittance's displacement, and
/// with it what the tank would give back, starts at the tracking lag).
inline void expectTheTanksHoldTheWorkAgainstTheThread(const RunResult& r, const Signals& signals) {
  const std::vector<double>& tension = r.value("thread tension at the end of each pull").values;
  const std::vector<double>& before = r.value("Endo Stitch tank at the start of each pull").values;
  const std::vector<double>& after = r.value("Endo Stitch tank at the end of each pull").values;
  ASSERT_EQ(before.size(), tension.size());
  ASSERT_EQ(after.size(), tension.size());
  for (std::size_t i = 0; i < tension.size(); ++i) {
    const double x = tension[i] / kContactStiffness;
    // Measured 1.18-1.25 times the spring's energy: the rest is the damping's dissipation at this pull's speed.
    const double spring = 0.5 * kContactVariable * x * x;
    EXPECT_GE(after[i] - before[i], 0.9 * spring) << "pull " << i + 1 << " at " << tension[i] << " N";
    EXPECT_LE(after[i] - before[i], 1.5 * spring) << "pull " << i + 1 << " at " << tension[i] << " N";
  }
  const std::vector<double>& hooking = r.value("stick tank before each hook").values;
  const std::vector<double>& pushed = r.value("stick tank after each push").values;
  ASSERT_EQ(hooking.size(), pushed.size());
  for (std::size_t i = 0; i < hooking.size(); ++i) EXPECT_GT(pushed[i], hooking[i]) << "hook " << i + 1;
  for (const char* tank : {"RightAdmittance.tankEnergy", "LeftAdmittance.tankEnergy"})
    EXPECT_GE(signals.minimum(tank), kTankInitialJ - 1e-3) << tank;
}

}  // namespace cobra::run::suturing_testing
