#pragma once
/// @file
/// The run's recorded columns (signals.csv): the ports of `run.record` and of the plots, and the
/// derived columns observers add (tracking errors, clearance, ...), sampled every record period.
/// An observer adds its columns at attach (ObserverContext::recording) and sets the derived ones
/// in a step whose Moment::records is true; the runner takes the row after the observers' step.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cobra/run/port_tap.hpp"

namespace cobra::run {

/// Columns sampled every record period, by name ("Comp.port", "Comp.port.z", "tracking.NAME.mm").
class Recording {
 public:
  /// Adds `path` (a port) unless recorded already. @throws as NumericTap.
  void addPort(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
               const std::string& use);
  /// A derived column (`unit` for the CSV header), filled through `set` before each row.
  std::size_t addDerived(const std::string& name, const std::string& unit);
  /// Sets a derived column's value for the next row (NaN until set: an empty cell). No allocation.
  void set(std::size_t derived, double value) { derived_now_[derived] = value; }
  /// One row at time `t` [s]: every port's newest value, the derived values set since.
  void sample(double t);

  /// The names of every column a plot may name (for messages), after at least one sample.
  std::vector<std::string> columnNames() const;
  /// The column `name`'s samples (times [s], values); false when it does not exist.
  bool column(const std::string& name, std::vector<double>& x, std::vector<double>& y) const;
  /// Whether `name` names a recorded port or field, or a derived column, or a port that has
  /// fields (then `fields` lists them).
  bool knows(const std::string& name, std::vector<std::string>& fields) const;
  std::string unitOf(const std::string& name) const;
  /// signals.csv: "time [s],NAME [unit],...", one row per sample.
  std::string csv() const;

 private:
  struct Port {
    std::unique_ptr<NumericTap> tap;
    std::vector<std::vector<double>> rows;  // one per sample (empty: no data yet)
    std::size_t width = 0;
  };
  std::vector<Port> ports_;
  std::vector<std::pair<std::string, std::string>> derived_;  // name, unit
  std::vector<double> derived_now_;
  std::vector<std::vector<double>> derived_rows_;
  std::vector<double> times_;
  std::vector<double> scratch_;
};

}  // namespace cobra::run
