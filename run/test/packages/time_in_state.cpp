// The package "cobra_time_in_state": an observer of a run written as an out-of-tree package
// would write it (built by cobra_add_package, loaded with packages_list = { "cobra_time_in_state" }).
// Its section of the `run` table,
//   time_in_state = { chart = "task" },
// adds the summary value "time in state, task": the time [s] the chart spent in each state it
// entered, in the order of first entry ("root.waiting 0.180 s, root.high 0.160 s, ...").
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cobra/deploy/package_registry.hpp"
#include "cobra/run/observer.hpp"
#include "cobra/run/runner.hpp"

namespace {

class TimeInState final : public cobra::run::Observer {
 public:
  TimeInState(std::string chart, cobra::run::Where where) : chart_name_(std::move(chart)), where_(std::move(where)) {}

  void attach(cobra::run::ObserverContext& run) override {
    chart_ = run.chart(chart_name_);
    if (chart_ == nullptr)
      throw std::runtime_error(where_.text() + ": run.time_in_state: unknown chart '" + chart_name_ + "'");
    states_.reserve(64);  // a chart has few states: no allocation as they come (but a new name's copy)
  }

  // Called at every observation and catch-up round; only a change of the chart's state does work.
  void step(const cobra::run::Moment& now) override {
    if (!chart_->changed) return;
    // The first observation's state is the one the run started in (one observation before).
    const double since = current_ == nullptr ? now.t - now.dt : now.t;
    if (current_ != nullptr) current_->seconds += now.t - entered_at_;
    current_ = &stateNamed(chart_->state);
    if (current_->first_entered < 0.0) current_->first_entered = since;
    entered_at_ = since;
  }

  void finish(cobra::run::RunResult& result) override {
    if (current_ != nullptr) current_->seconds += result.duration - entered_at_;
    cobra::run::SummaryValue value{"time in state, " + chart_name_, "s", {}, {}, {}};
    for (const State& s : states_) {
      value.values.push_back(s.seconds);
      value.times.push_back(s.first_entered);
      char text[32];
      std::snprintf(text, sizeof text, " %.3f s", s.seconds);
      value.text += (value.text.empty() ? "" : ", ") + s.name + text;
    }
    result.summary.push_back(std::move(value));
  }

 private:
  struct State {
    std::string name;
    double seconds = 0.0, first_entered = 0.0;
  };
  State& stateNamed(const std::string& name) {
    for (State& s : states_)
      if (s.name == name) return s;
    states_.push_back({name, 0.0, 0.0});
    states_.back().first_entered = -1.0;
    return states_.back();
  }

  std::string chart_name_;
  cobra::run::Where where_;
  const cobra::run::ChartState* chart_ = nullptr;
  std::vector<State> states_;
  State* current_ = nullptr;
  double entered_at_ = 0.0;  // s
};

}  // namespace

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  cobra::run::ObserverRegistry::add(
      package, "time_in_state", "the time [s] a chart spent in each state (a summary value)",
      [](const cobra::run::Section& section) -> std::unique_ptr<cobra::run::Observer> {
        section.allowOnly({"chart"});
        return std::make_unique<TimeInState>(section.string("chart", true), section.where());
      });
}
