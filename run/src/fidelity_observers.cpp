// The fidelity observers: `tracking` (commanded against measured tool pose every step, with the
// joint-jump check) and `clearance` (the measured state's clearance against its threshold, the
// declared contacts apart). Each fills its part of RunResult, adds derived columns and the
// report's rows and figures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <lua.hpp>

#include "builtin_observers.hpp"
#include "cobra/core/component.hpp"
#include "cobra/deploy/configurator.hpp"
#include "cobra/run/runner.hpp"
#include "lua_reader.hpp"

namespace cobra::run {
namespace {

using detail::Reader;

Panel panel(const Recording& recording, std::string title, std::string x_label, std::string y_label,
            const std::vector<std::pair<std::string, std::string>>& series, bool dashed_last = false) {
  Panel p{std::move(title), std::move(x_label), std::move(y_label), {}};
  for (std::size_t i = 0; i < series.size(); ++i) {
    Series s{series[i].second, {}, {}, dashed_last && i + 1 == series.size()};
    recording.column(series[i].first, s.x, s.y);
    if (!s.x.empty()) p.series.push_back(std::move(s));
  }
  return p;
}

// `panel` of one column with a dashed horizontal line at `limit` over the same times.
Panel panelWithLimit(const Recording& recording, std::string title, std::string y_label, const std::string& column,
                     const std::string& label, double limit, const std::string& limit_label) {
  Panel p = panel(recording, std::move(title), "t [s]", std::move(y_label), {{column, label}});
  if (p.series.empty()) return p;
  const std::vector<double>& x = p.series.front().x;
  p.series.push_back({limit_label, {x.front(), x.back()}, {limit, limit}, true});
  return p;
}

std::string millimetres(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f mm", 1000.0 * metres);
  return text;
}

std::string worstText(const Worst& worst, const char* unit) {
  char text[96];
  std::snprintf(text, sizeof text, "%.2f %s at %.3f s", worst.value, unit, worst.at);
  return text + (worst.state.empty() ? std::string() : " (" + worst.state + ")");
}

bool containsAny(const std::string& text, const std::vector<std::string>& any) {
  return std::any_of(any.begin(), any.end(), [&](const std::string& s) { return text.find(s) != std::string::npos; });
}

// `run.tracking`: one monitor per tool.
class TrackingObserver final : public Observer {
 public:
  void attach(ObserverContext& run) override {
    run_ = &run;
    for (const TrackingSpec& t : run.spec.tracking) {
      Tracker tracker;
      tracker.spec = &t;
      const std::string at = t.where.text(), use = "run.tracking '" + t.name + "'";
      tracker.commanded = std::make_unique<Tap<KDL::Frame>>(run.components, t.commanded, at, use, "KDL.Frame");
      tracker.measured = std::make_unique<Tap<KDL::Frame>>(run.components, t.measured, at, use, "KDL.Frame");
      std::vector<double> limits = t.max_velocity_values;
      if (!t.joints.empty())
        tracker.joints = std::make_unique<Tap<KDL::JntArray>>(run.components, t.joints, at, use, "KDL.JntArray");
      if (!t.joints.empty() && limits.empty()) {
        core::Component* owner = ownerOf(run.components, t.max_velocity, false);
        if (owner == nullptr)
          throw std::runtime_error(at + ": " + use + ": max_velocity '" + t.max_velocity +
                                   "' is not a property Comp.name of the deployment");
        limits = owner->getProperty<std::vector<double>>(memberOf(t.max_velocity));
        if (limits.empty())
          throw std::runtime_error(at + ": " + use + ": " + t.max_velocity +
                                   " is empty: the joint-jump check needs the joints' velocity limits (rad/s, m/s)");
      }
      tracker.chart = t.chart.empty() ? nullptr : run.chart(t.chart);
      if (!t.chart.empty() && tracker.chart == nullptr)
        throw std::runtime_error(at + ": " + use + ": unknown chart '" + t.chart + "'");
      tracker.limits = limits.size();
      tracker.monitor = std::make_unique<TrackingMonitor>(t.name, limits, run.spec.step);
      // Wall clock: the joints read at a sample were published by the robot's own thread up to one
      // of its periods before.
      if (run.realtime) tracker.monitor->setSampleSkew(run.spec.step);
      tracker.mm_column = run.recording.addDerived("tracking." + t.name + ".mm", "mm");
      tracker.deg_column = run.recording.addDerived("tracking." + t.name + ".deg", "deg");
      trackers_.push_back(std::move(tracker));
    }
  }

  void step(const Moment& now) override {
    if (!now.full) return;
    static const std::string kNoState;
    const std::uint64_t switches = run_->configurator.switchCount();
    if (switches != switches_seen_) {  // the same count, the same deployments (looked up in maps otherwise)
      switches_seen_ = switches;
      for (Tracker& tr : trackers_) {
        const auto& counting = tr.spec->counts_while;
        tr.counts = counting.empty() || std::find(counting.begin(), counting.end(),
                                                  run_->configurator.currentDeployment(tr.spec->scope)) != counting.end();
      }
    }
    for (Tracker& tr : trackers_) {
      KDL::Frame commanded, measured;
      KDL::JntArray& q = tr.joint_sample;  // kept: reading into it reuses its storage
      if (tr.commanded->read(commanded) && tr.measured->read(measured)) {
        const bool have_q = tr.joints && tr.joints->read(q);
        if (have_q && q.rows() != tr.limits)
          throw std::runtime_error(tr.spec->where.text() + ": run.tracking '" + tr.spec->name + "': " + tr.spec->joints +
                                   " has " + std::to_string(q.rows()) + " joints but max_velocity gives " +
                                   std::to_string(tr.limits) + " limits");
        tr.monitor->step(now.t, tr.counts, tr.chart ? tr.chart->state : kNoState, commanded, measured,
                         have_q ? &q : nullptr);
      }
      if (now.records) {
        const auto [mm, deg] = tr.monitor->takeWindowMaximum();
        run_->recording.set(tr.mm_column, mm);
        run_->recording.set(tr.deg_column, deg);
      }
    }
  }

  void finish(RunResult& result) override {
    for (const Tracker& tr : trackers_) result.tracking.push_back(tr.monitor->figures());
  }

  void report(RunReport& report, const Recording& recording) const override {
    for (const Tracker& tr : trackers_) {
      const TrackingFigures& robot = tr.monitor->figures();
      const TrackingSpec& t = *tr.spec;
      std::string when = "every sample";
      if (!t.counts_while.empty()) {
        when = "while the " + (t.scope.empty() ? std::string("default") : t.scope) + " deployment is ";
        for (std::size_t d = 0; d < t.counts_while.size(); ++d) when += (d ? " or " : "") + t.counts_while[d];
      }
      char above[96];
      std::snprintf(above, sizeof above, "%.3f s above 5 mm of %.1f s sampled; largest command step %.3f mm at %.3f s",
                    robot.seconds_above_5mm, robot.seconds_sampled, 1000.0 * robot.max_command_step,
                    robot.max_command_step_at);
      report.summary.push_back({"worst tracking, " + robot.robot + " (" + when + ")",
                                worstText(robot.position_mm, "mm") + "; " + worstText(robot.orientation_deg, "deg") + "; " + above});
      if (!t.joints.empty())
        report.summary.push_back({"joints at their velocity limit, " + robot.robot,
                                  std::to_string(robot.joint_jumps) + " episodes; fastest " +
                                      worstText({100.0 * robot.joint_speed.value, robot.joint_speed.at, robot.joint_speed.state},
                                                "% of the limit")});
    }
    for (const Tracker& tr : trackers_) {
      const TrackingSpec& t = *tr.spec;
      const std::string base = "tracking." + t.name;
      report.figures.push_back({"Tool tracking error, " + t.name + " (commanded " + t.commanded + ", measured " + t.measured + ")",
                                {panelWithLimit(recording, "position error (largest per record period)", "error [mm]",
                                                base + ".mm", t.name, t.accept_mm, "acceptance"),
                                 panelWithLimit(recording, "orientation error (largest per record period)", "error [deg]",
                                                base + ".deg", t.name, t.accept_deg, "acceptance")}});
    }
  }

 private:
  struct Tracker {
    const TrackingSpec* spec = nullptr;
    std::unique_ptr<Tap<KDL::Frame>> commanded, measured;
    std::unique_ptr<Tap<KDL::JntArray>> joints;
    std::unique_ptr<TrackingMonitor> monitor;
    std::size_t limits = 0;  // joint velocity limits given
    std::size_t mm_column = 0, deg_column = 0;
    const ChartState* chart = nullptr;  // spec->chart's (nullptr: none)
    KDL::JntArray joint_sample;         // the joints' last sample (kept: reading it allocates once)
    bool counts = false;                // spec->scope's deployment is one of counts_while (or none given)
  };
  ObserverContext* run_ = nullptr;
  std::vector<Tracker> trackers_;
  std::uint64_t switches_seen_ = UINT64_MAX;  // Configurator::switchCount() when last looked (max: never)
};

// `run.clearance`: the port's samples against the threshold, the contacts apart.
class ClearanceObserver final : public Observer {
 public:
  void attach(ObserverContext& run) override {
    run_ = &run;
    const ClearanceSpec& spec = run.spec.clearance;
    ClearanceFigures& figures = run.result.clearance;
    const std::string at = spec.where.text();
    clearance_ = std::make_unique<Tap<double>>(run.components, spec.port, at, "run.clearance", "double (m)");
    for (const auto& [name, port] : spec.contacts) {
      contacts_.push_back(std::make_unique<Tap<double>>(run.components, port, at, "run.clearance contact '" + name + "'", "double (m)"));
      contact_columns_.push_back(run.recording.addDerived("contact." + name, "m"));
      figures.contacts.emplace_back(name, std::numeric_limits<double>::infinity());
    }
    for (const ClearancePause& pause : spec.pauses) {
      pause_charts_.push_back(run.chart(pause.chart));
      if (pause_charts_.back() == nullptr)
        throw std::runtime_error(at + ": run.clearance pause '" + pause.name + "': unknown chart '" + pause.chart + "'");
    }
    paused_.assign(spec.pauses.size(), false);
    figures.threshold = spec.threshold;
    if (!spec.threshold_operation.empty()) {
      core::Component* owner = ownerOf(run.components, spec.threshold_operation, true);
      if (owner == nullptr)
        throw std::runtime_error(at + ": run.clearance: threshold '" + spec.threshold_operation +
                                 "' is not an operation Comp.name");
      figures.threshold = owner->call<double>(memberOf(spec.threshold_operation));
    }
    column_ = run.recording.addDerived("clearance", "m");
    threshold_column_ = run.recording.addDerived("clearance.threshold", "m");
    if (!spec.pairs.empty()) attachPairs(run, spec, figures);
  }

  void step(const Moment& now) override {
    if (!now.full) return;
    const ClearanceSpec& spec = run_->spec.clearance;
    ClearanceFigures& figures = run_->result.clearance;
    for (std::size_t p = 0; p < spec.pauses.size(); ++p) {
      const ClearancePause& pause = spec.pauses[p];
      const ChartState& chart = *pause_charts_[p];
      if (!chart.changed) continue;  // the same state decides the same
      if (containsAny(chart.state, pause.from)) paused_[p] = true;
      else if (containsAny(chart.state, pause.to)) paused_[p] = false;
    }
    const bool counts = std::none_of(paused_.begin(), paused_.end(), [](bool b) { return b; });
    double d = NAN;
    if (!counts) {
      figures.last = NAN;
    } else if (clearance_->read(d)) {
      figures.last = d;
      figures.seconds_sampled += now.dt;
      if (std::isnan(d)) {
        ++figures.unreachable;
      } else {
        if (d <= figures.threshold) figures.seconds_below += now.dt;
        if (d < figures.worst) {
          figures.worst = d, figures.worst_at = now.t;
          figures.worst_state.clear();
          for (const ChartState* c : run_->charts)
            figures.worst_state += (figures.worst_state.empty() ? "" : ", ") + c->spec->name + " " + c->state;
        }
      }
    }
    if (pairs_ != nullptr) stepPairs(now, counts);
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
      double contact = NAN;
      if (!contacts_[k]->read(contact) || std::isnan(contact)) continue;
      figures.contacts[k].second = std::min(figures.contacts[k].second, contact);
      run_->recording.set(contact_columns_[k], contact);
    }
    if (now.records) {
      run_->recording.set(column_, figures.last);
      run_->recording.set(threshold_column_, figures.threshold);
      for (std::size_t k = 0; k < pair_columns_.size(); ++k) run_->recording.set(pair_columns_[k], pair_last_[k]);
    }
  }

  void report(RunReport& report, const Recording& recording) const override {
    const ClearanceSpec& spec = run_->spec.clearance;
    const ClearanceFigures& c = run_->result.clearance;
    char below[128];
    std::snprintf(below, sizeof below, "; %.3f s at or under the threshold of %.1f s counted; %d unmeasurable samples",
                  c.seconds_below, c.seconds_sampled, c.unreachable);
    report.summary.push_back({"worst clearance (threshold " + millimetres(c.threshold) + ", allowed contacts apart)",
                              std::isinf(c.worst) ? std::string("-")
                                                  : millimetres(c.worst) + " at" + seconds(c.worst_at) + " (" +
                                                        c.worst_state + ")" + below});
    // Each declared contact on its own row: a contact the task makes on purpose is not a clearance.
    for (const auto& [name, distance] : c.contacts)
      report.summary.push_back({"allowed contact '" + name + "', smallest distance (0: touching or inside)",
                                std::isinf(distance) ? std::string("-") : millimetres(distance)});
    std::string paused;
    for (const ClearancePause& pause : spec.pauses) paused += (paused.empty() ? "" : ", ") + pause.name;
    if (!paused.empty()) report.summary.push_back({"clearance not counted while", paused});
    // Each pair of groups on its own row: which two came closest, when and where.
    for (const ClearanceFigures::Pair& pair : c.pairs)
      report.summary.push_back({"clearance of the pair " + pair.name + " (its smallest)",
                                std::isinf(pair.worst) ? std::string("-")
                                                       : millimetres(pair.worst) + " at" + seconds(pair.worst_at) +
                                                             " (" + pair.worst_state + ")"});
    std::vector<std::pair<std::string, std::string>> contacts;
    for (const auto& [name, port] : spec.contacts) contacts.emplace_back("contact." + name, name);
    report.figures.push_back({"Minimum collision distance of the measured state (" + spec.port + ")",
                              {panel(recording, "clearance against its threshold", "t [s]", "distance [m]",
                                     {{"clearance", "clearance"}, {"clearance.threshold", "clearance threshold"}}, true),
                               panel(recording, "allowed contacts (0: touching or inside)", "t [s]", "distance [m]", contacts)}});
    if (!c.pairs.empty()) {
      std::vector<std::pair<std::string, std::string>> pairs;
      for (const ClearanceFigures::Pair& pair : c.pairs) pairs.emplace_back("clearance." + pair.name, pair.name);
      pairs.emplace_back("clearance.threshold", "clearance threshold");
      report.figures.push_back({"Clearance per pair of groups (" + spec.pairs + ")",
                                {panel(recording, "each pair's clearance against the threshold", "t [s]", "distance [m]",
                                       pairs, true)}});
    }
  }

 private:
  // `pairs`: the names from the `pair_names` operation (comma-separated), one derived column
  // "clearance.NAME" each; the port's sample and the worst states sized here, not per step.
  void attachPairs(ObserverContext& run, const ClearanceSpec& spec, ClearanceFigures& figures) {
    const std::string at = spec.pairs_where.text();
    pairs_ = std::make_unique<Tap<std::vector<double>>>(run.components, spec.pairs, at, "run.clearance pairs",
                                                        "vector<double> (m per pair)");
    core::Component* owner = ownerOf(run.components, spec.pair_names, true);
    if (owner == nullptr)
      throw std::runtime_error(at + ": run.clearance: pair_names '" + spec.pair_names +
                               "' is not an operation Comp.name (returning the pairs' names, comma-separated)");
    const std::string names = owner->call<std::string>(memberOf(spec.pair_names));
    for (std::size_t from = 0; from < names.size();) {
      const std::size_t comma = std::min(names.find(',', from), names.size());
      if (comma > from) figures.pairs.emplace_back().name = names.substr(from, comma - from);
      from = comma + 1;
    }
    if (figures.pairs.empty())
      throw std::runtime_error(at + ": run.clearance: pair_names '" + spec.pair_names + "' names no pair");
    for (ClearanceFigures::Pair& pair : figures.pairs) {
      pair_columns_.push_back(run.recording.addDerived("clearance." + pair.name, "m"));
      pair.worst_state.reserve(kStateReserve);
    }
    pair_values_.reserve(figures.pairs.size());
    pair_last_.assign(figures.pairs.size(), NAN);
  }

  // Each pair's newest clearance, its worst while the clearance counts (no allocation: the
  // sample's and the states' room was made at attach; a longer state text than that grows once).
  void stepPairs(const Moment& now, bool counts) {
    std::vector<ClearanceFigures::Pair>& pairs = run_->result.clearance.pairs;
    std::fill(pair_last_.begin(), pair_last_.end(), NAN);
    if (!counts || !pairs_->read(pair_values_)) return;
    for (std::size_t k = 0; k < pairs.size() && k < pair_values_.size(); ++k) {
      const double d = pair_values_[k];
      pair_last_[k] = d;
      if (std::isnan(d) || d >= pairs[k].worst) continue;
      pairs[k].worst = d, pairs[k].worst_at = now.t;
      std::string& state = pairs[k].worst_state;
      state.clear();
      for (const ChartState* c : run_->charts) {
        if (!state.empty()) state += ", ";
        state.append(c->spec->name).append(" ").append(c->state);
      }
    }
  }

  static constexpr std::size_t kStateReserve = 256;  // characters of "needle root.X, us root.Y"
  ObserverContext* run_ = nullptr;
  std::unique_ptr<Tap<double>> clearance_;
  std::vector<std::unique_ptr<Tap<double>>> contacts_;
  std::vector<bool> paused_;                  // per pause
  std::vector<const ChartState*> pause_charts_;  // per pause: its chart
  std::size_t column_ = 0, threshold_column_ = 0;
  std::vector<std::size_t> contact_columns_;
  std::unique_ptr<Tap<std::vector<double>>> pairs_;  // nullptr: no `pairs`
  std::vector<double> pair_values_, pair_last_;     // m per pair: the port's sample, the recorded value
  std::vector<std::size_t> pair_columns_;
};

}  // namespace

ObserverRegistry::Kind trackingObserver() {
  return {"tracking", "commanded against measured tool pose every step, joint jumps (fidelity figures)", "cobra",
          [](const Section& section) -> std::unique_ptr<Observer> {
            std::vector<TrackingSpec>& out = section.spec().tracking;
            lua_State* L = section.state();
            section.reader().items([&](Reader& t) {
              TrackingSpec tracking;
              tracking.name = t.string("name", true);
              tracking.commanded = t.string("commanded", true);
              tracking.measured = t.string("measured", true);
              tracking.joints = t.string("joints", false);
              lua_getfield(L, -1, "max_velocity");
              const bool listed = lua_istable(L, -1);
              lua_pop(L, 1);
              if (listed) {
                tracking.max_velocity_values = t.numbers("max_velocity");
              } else {
                tracking.max_velocity = t.string("max_velocity", false);
              }
              if (!tracking.joints.empty() && tracking.max_velocity.empty() && tracking.max_velocity_values.empty())
                t.fail("`joints` needs `max_velocity = \"Comp.property\"` or { limits } (the joints' velocity limits, "
                       "rad/s or m/s)");
              tracking.chart = t.string("chart", false);
              tracking.accept_mm = t.number("accept_mm", tracking.accept_mm, true);
              tracking.accept_deg = t.number("accept_deg", tracking.accept_deg, true);
              t.table("counts_while", [&](const Reader& counts) {
                tracking.scope = counts.string("scope", false);
                tracking.counts_while = counts.strings("deployments");
              });
              tracking.where = t.where();
              out.push_back(std::move(tracking));
            });
            return std::make_unique<TrackingObserver>();
          }};
}

ObserverRegistry::Kind clearanceObserver() {
  return {"clearance", "the measured state's clearance against its threshold, declared contacts apart", "cobra",
          [](const Section& section) -> std::unique_ptr<Observer> {
            const Reader& c = section.reader();
            lua_State* L = section.state();
            if (!lua_istable(L, -1)) c.fail("must be a table");
            ClearanceSpec& clearance = section.spec().clearance;
            clearance.declared = true;
            clearance.port = c.string("port", true);
            clearance.where = {c.where().file, c.lineOf(clearance.port)};
            lua_getfield(L, -1, "threshold");
            if (lua_type(L, -1) == LUA_TNUMBER) {
              clearance.threshold = lua_tonumber(L, -1);
            } else if (lua_type(L, -1) == LUA_TSTRING) {
              clearance.threshold_operation = lua_tostring(L, -1);
            } else {
              lua_pop(L, 1);
              c.fail("needs `threshold` (m, a number, or \"Comp.operation\" returning it)");
            }
            lua_pop(L, 1);
            c.list("contacts", [&](Reader& contact) {
              clearance.contacts.emplace_back(contact.string("name", true), contact.string("port", true));
            });
            clearance.pairs = c.string("pairs", false);
            clearance.pair_names = c.string("pair_names", false);
            clearance.pairs_where = {c.where().file, c.lineOf(clearance.pairs.empty() ? clearance.pair_names : clearance.pairs)};
            if (clearance.pairs.empty() != clearance.pair_names.empty())
              throw std::runtime_error(clearance.pairs_where.text() + ": " + c.path() +
                                       ": `pairs` (a vector<double> port, m per pair) and `pair_names` "
                                       "(\"Comp.operation\" naming them) go together");
            c.list("pauses", [&](Reader& pause) {
              clearance.pauses.push_back(
                  {pause.string("name", true), pause.string("chart", true), pause.strings("from"), pause.strings("to")});
            });
            return std::make_unique<ClearanceObserver>();
          }};
}

}  // namespace cobra::run
