#pragma once
// What the Puma 260 tests (task_test.cpp, faults_test.cpp) share: a run of apps/puma260 through
// the runner's API (what `cobra run apps/puma260` does), its recorded signals (signals.csv) and
// when each phase of the chart began.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cobra/run/runner.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run::puma260 {

inline const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "apps" / "puma260";
inline const std::filesystem::path kFaults = kApp / "test" / "faults";

/// A run of scenario `scenario` (a folder of scenarios/) writing its run folder under the temp
/// directory (`name`: one per test, ctest runs them in parallel).
inline RunOptions options(const std::string& scenario, const std::string& name) {
  RunOptions o;
  o.app = kApp;
  o.scenario = kApp / "scenarios" / scenario;
  o.time_limit = 120.0;  // s simulated; the task takes about 20 s
  o.report_folder = ::cobra::test_support::scratchPath("cobra_puma260_" + name);
  std::filesystem::remove_all(o.report_folder);
  return o;
}

/// signals.csv of a run folder: a column per recorded value, named as in the header without its unit.
class Signals {
 public:
  explicit Signals(const std::filesystem::path& csv) {
    std::ifstream in(csv);
    std::string line;
    if (!std::getline(in, line)) return;
    // Header cells are "name [unit]", quoted when the unit holds a comma ("[N, N·m]").
    std::string cell;
    bool quoted = false;
    for (const char c : line + ",") {
      if (c == ',' && !quoted) {
        names_.push_back(cell.substr(0, cell.find(" [")));
        cell.clear();
      } else if (c == '"') {
        quoted = !quoted;
      } else {
        cell += c;
      }
    }
    while (std::getline(in, line)) {
      std::vector<double> row;
      std::stringstream cells(line);
      for (std::string value; std::getline(cells, value, ',');) row.push_back(value.empty() ? NAN : std::strtod(value.c_str(), nullptr));
      row.resize(names_.size(), NAN);
      rows_.push_back(std::move(row));
    }
  }
  std::size_t size() const { return rows_.size(); }
  /// The value of column `name` in row `i` (NaN before the port had data).
  double operator()(std::size_t i, const std::string& name) const {
    const auto it = std::find(names_.begin(), names_.end(), name);
    if (it == names_.end()) ADD_FAILURE() << "signals.csv has no column " << name;
    return it == names_.end() ? NAN : rows_[i][static_cast<std::size_t>(it - names_.begin())];
  }
  double time(std::size_t i) const { return rows_[i][0]; }

 private:
  std::vector<std::string> names_;
  std::vector<std::vector<double>> rows_;
};

/// When the chart first was in a state whose path starts with `state` (from the event log: the
/// chart's state after each event); +inf when never.
inline double began(const RunResult& r, const std::string& state) {
  for (const report::EventRecord& e : r.events)
    if (e.state.rfind(state, 0) == 0) return e.time;
  return INFINITY;
}

/// When `source` first raised `event` at or after `after` s; +inf when it did not.
inline double raised(const RunResult& r, const std::string& source, const std::string& event, double after = 0.0) {
  for (const report::EventRecord& e : r.events)
    if (e.time >= after && e.source == source && e.event.rfind(event, 0) == 0 &&
        (e.event.size() == event.size() || e.event[event.size()] == ' '))
      return e.time;
  return INFINITY;
}

/// Whether `lines` appear in the run's log in this order (other lines between them).
inline void expectInOrder(const RunResult& r, const std::vector<std::string>& lines) {
  std::size_t at = 0;
  for (const std::string& line : lines) {
    const auto it = std::find_if(r.log.begin() + static_cast<std::ptrdiff_t>(at), r.log.end(),
                                 [&](const std::string& l) { return l.find(line) != std::string::npos; });
    if (it == r.log.end()) {
      std::string log;
      for (const std::string& l : r.log) log += "  " + l + "\n";
      ADD_FAILURE() << "'" << line << "' not found after position " << at << " of the log:\n" << log;
      return;
    }
    at = static_cast<std::size_t>(it - r.log.begin()) + 1;
  }
}

inline std::size_t count(const RunResult& r, const std::string& line) {
  return static_cast<std::size_t>(
      std::count_if(r.log.begin(), r.log.end(), [&](const std::string& l) { return l.find(line) != std::string::npos; }));
}

}  // namespace cobra::run::puma260
