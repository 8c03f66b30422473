#include "observers.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>

namespace cobra::run {

bool startsWith(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

std::string seconds(double t) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%8.3f s", t);
  return buffer;
}

void Recording::addPort(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
                        const std::string& use) {
  for (const Port& p : ports_)
    if (p.tap->path() == path) return;
  ports_.push_back({std::make_unique<NumericTap>(registry, path, where, use), {}, 0});
}

std::size_t Recording::addDerived(const std::string& name, const std::string& unit) {
  derived_.emplace_back(name, unit);
  derived_now_.push_back(std::numeric_limits<double>::quiet_NaN());
  return derived_.size() - 1;
}

void Recording::sample(double t) {
  times_.push_back(t);
  for (Port& p : ports_) {
    p.tap->read(scratch_);
    p.width = std::max(p.width, scratch_.size());
    p.rows.push_back(scratch_);
  }
  derived_rows_.push_back(derived_now_);
  std::fill(derived_now_.begin(), derived_now_.end(), std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> Recording::columnNames() const {
  std::vector<std::string> names;
  for (const Port& p : ports_)
    for (const std::string& field : p.tap->fields(p.width))
      names.push_back(field.empty() ? p.tap->path() : p.tap->path() + (field[0] == '[' ? "" : ".") + field);
  for (const auto& [name, unit] : derived_) names.push_back(name);
  return names;
}

bool Recording::knows(const std::string& name, std::vector<std::string>& fields) const {
  fields.clear();
  for (const auto& [derived, unit] : derived_)
    if (derived == name) return true;
  for (const Port& p : ports_) {
    const std::string& path = p.tap->path();
    if (name.rfind(path, 0) != 0) continue;
    const std::string rest = name.substr(path.size());
    const std::vector<std::string> known = p.tap->fields(0);
    if (rest.empty()) {
      if (known.size() == 1 && known[0].empty()) return true;
      fields = known.empty() ? std::vector<std::string>{"[0]", "[1]", "..."} : known;
      return false;
    }
    if (rest[0] == '[') return known.empty() && rest.back() == ']';
    if (rest[0] == '.') return std::find(known.begin(), known.end(), rest.substr(1)) != known.end();
  }
  return false;
}

std::string Recording::unitOf(const std::string& name) const {
  for (const auto& [derived, unit] : derived_)
    if (derived == name) return unit;
  for (const Port& p : ports_)
    if (name.rfind(p.tap->path(), 0) == 0) {
      const std::string rest = name.substr(p.tap->path().size());
      return rest.size() > 1 && rest[1] == 'q' ? "1" : p.tap->unit();  // quaternions are dimensionless
    }
  return "";
}

bool Recording::column(const std::string& name, std::vector<double>& x, std::vector<double>& y) const {
  x.clear();
  y.clear();
  for (std::size_t d = 0; d < derived_.size(); ++d) {
    if (derived_[d].first != name) continue;
    for (std::size_t i = 0; i < times_.size(); ++i)
      if (std::isfinite(derived_rows_[i][d])) x.push_back(times_[i]), y.push_back(derived_rows_[i][d]);
    return true;
  }
  for (const Port& p : ports_) {
    const std::vector<std::string> fields = p.tap->fields(p.width);
    for (std::size_t f = 0; f < fields.size(); ++f) {
      const std::string full =
          fields[f].empty() ? p.tap->path() : p.tap->path() + (fields[f][0] == '[' ? "" : ".") + fields[f];
      if (full != name) continue;
      for (std::size_t i = 0; i < times_.size(); ++i)
        if (f < p.rows[i].size() && std::isfinite(p.rows[i][f])) x.push_back(times_[i]), y.push_back(p.rows[i][f]);
      return true;
    }
  }
  return false;
}

std::string Recording::csv() const {
  std::string out = "time [s]";
  auto header = [&](const std::string& name, const std::string& unit) {
    const std::string cell = name + (unit.empty() ? "" : " [" + unit + "]");  // a unit may hold a comma: "N, N·m"
    const bool quote = cell.find(',') != std::string::npos;
    out += "," + std::string(quote ? "\"" : "") + cell + (quote ? "\"" : "");
  };
  for (const std::string& name : columnNames()) header(name, unitOf(name));
  out += "\n";
  char number[32];
  auto put = [&](double v) {
    if (std::isfinite(v)) {
      std::snprintf(number, sizeof number, ",%.6g", v);
      out += number;
    } else {
      out += ",";
    }
  };
  for (std::size_t i = 0; i < times_.size(); ++i) {
    std::snprintf(number, sizeof number, "%.3f", times_[i]);
    out += number;
    for (const Port& p : ports_) {
      const std::size_t width = std::max<std::size_t>(p.width, 1);
      for (std::size_t f = 0; f < width; ++f) put(f < p.rows[i].size() ? p.rows[i][f] : std::nan(""));
    }
    for (const double v : derived_rows_[i]) put(v);
    out += "\n";
  }
  return out;
}

namespace {

plot::Panel panel(const Recording& recording, std::string title, std::string x_label, std::string y_label,
                  const std::vector<std::pair<std::string, std::string>>& series, bool dashed_last = false) {
  plot::Panel p{std::move(title), std::move(x_label), std::move(y_label), {}};
  for (std::size_t i = 0; i < series.size(); ++i) {
    plot::Series s{series[i].second, {}, {}, dashed_last && i + 1 == series.size()};
    recording.column(series[i].first, s.x, s.y);
    if (!s.x.empty()) p.series.push_back(std::move(s));
  }
  return p;
}

// `panel` of one column with a dashed horizontal line at `limit` over the same times.
plot::Panel panelWithLimit(const Recording& recording, std::string title, std::string y_label, const std::string& column,
                           const std::string& label, double limit, const std::string& limit_label) {
  plot::Panel p = panel(recording, std::move(title), "t [s]", std::move(y_label), {{column, label}});
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

// When chart `chart` first entered a state whose path starts with `state` (s; nullopt: never).
std::optional<double> firstEntered(const std::vector<report::StateInterval>& timeline, const std::string& chart,
                                   const std::string& state) {
  const std::string lane = chart + " chart";
  const auto entered = std::find_if(timeline.begin(), timeline.end(), [&](const report::StateInterval& interval) {
    return interval.chart == lane && interval.state.rfind(state, 0) == 0;
  });
  if (entered == timeline.end()) return std::nullopt;
  return entered->begin;
}

// Column `y` against column `x` at their common sample times from `from` s on, the marks placed on it.
plot::Series pathSeries(const Recording& recording, const PathSpec& path,
                        const std::vector<report::StateInterval>& timeline, double from) {
  plot::Series s{path.label, {}, {}, path.dashed};
  std::vector<double> xt, xv, yt, yv, times;
  recording.column(path.x, xt, xv);
  recording.column(path.y, yt, yv);
  for (std::size_t i = 0, j = 0; i < xt.size(); ++i) {
    while (j < yt.size() && yt[j] < xt[i]) ++j;
    if (j < yt.size() && yt[j] == xt[i] && xt[i] >= from)
      s.x.push_back(xv[i]), s.y.push_back(yv[j]), times.push_back(xt[i]);
  }
  for (const PathSpec::Mark& mark : path.marks) {
    const std::optional<double> begin = firstEntered(timeline, mark.chart, mark.state);
    if (!begin || *begin < from) continue;
    if (times.empty()) break;
    // Entered after the last sample (e.g. the final state, which ends the run): the last sample.
    const auto at = std::lower_bound(times.begin(), times.end(), *begin);
    const std::size_t k = std::min(static_cast<std::size_t>(at - times.begin()), times.size() - 1);
    s.marker_x.push_back(s.x[k]);
    s.marker_y.push_back(s.y[k]);
    s.marker_labels.push_back(mark.label);
  }
  return s;
}

}  // namespace

std::vector<plot::Figure> reportFigures(const RunSpec& spec, const Recording& recording,
                                        const std::vector<Tracker>& trackers, const ClearanceObserver* clearance,
                                        const std::vector<report::StateInterval>& timeline) {
  std::vector<plot::Figure> out;
  for (const PlotSpec& p : spec.plots) {
    if (!p.paths.empty()) {
      plot::Panel paths{p.title, p.paths.front().x + (p.x_unit.empty() ? "" : " [" + p.x_unit + "]"),
                        p.paths.front().y + (p.unit.empty() ? "" : " [" + p.unit + "]"), {}};
      double from = 0.0;
      if (!p.from_chart.empty()) from = firstEntered(timeline, p.from_chart, p.from_state).value_or(INFINITY);
      for (const PathSpec& path : p.paths) {
        plot::Series s = pathSeries(recording, path, timeline, from);
        if (!s.x.empty()) paths.series.push_back(std::move(s));
      }
      out.push_back({p.title, {std::move(paths)}});
      continue;
    }
    plot::Panel one{p.title, p.x.empty() ? "t [s]" : p.x + (p.x_unit.empty() ? "" : " [" + p.x_unit + "]"),
                    p.unit.empty() ? "value" : "[" + p.unit + "]", {}};
    for (const std::string& name : p.series) {
      plot::Series s{name, {}, {}};
      recording.column(name, s.x, s.y);
      if (!p.x.empty()) {  // against another column, at the same sample times
        std::vector<double> xt, xv;
        recording.column(p.x, xt, xv);
        std::vector<double> x, y;
        for (std::size_t i = 0, j = 0; i < s.x.size(); ++i) {
          while (j < xt.size() && xt[j] < s.x[i]) ++j;
          if (j < xt.size() && xt[j] == s.x[i]) x.push_back(xv[j]), y.push_back(s.y[i]);
        }
        s.x = std::move(x);
        s.y = std::move(y);
      }
      if (!s.x.empty()) one.series.push_back(std::move(s));
    }
    out.push_back({p.title, {std::move(one)}});
  }
  for (const Tracker& t : trackers) {
    const std::string base = "tracking." + t.spec.name;
    out.push_back({"Tool tracking error, " + t.spec.name + " (commanded " + t.spec.commanded + ", measured " +
                       t.spec.measured + ")",
                   {panelWithLimit(recording, "position error (largest per record period)", "error [mm]", base + ".mm",
                                   t.spec.name, t.spec.accept_mm, "acceptance"),
                    panelWithLimit(recording, "orientation error (largest per record period)", "error [deg]",
                                   base + ".deg", t.spec.name, t.spec.accept_deg, "acceptance")}});
  }
  if (clearance != nullptr) {
    std::vector<std::pair<std::string, std::string>> contacts;
    for (const auto& [name, port] : clearance->spec.contacts) contacts.emplace_back("contact." + name, name);
    out.push_back({"Minimum collision distance of the measured state (" + clearance->spec.port + ")",
                   {panel(recording, "clearance against its threshold", "t [s]", "distance [m]",
                          {{"clearance", "clearance"}, {"clearance.threshold", "clearance threshold"}}, true),
                    panel(recording, "allowed contacts (0: touching or inside)", "t [s]", "distance [m]", contacts)}});
  }
  for (plot::Figure& f : out)
    std::erase_if(f.panels, [](const plot::Panel& p) { return p.series.empty(); });
  std::erase_if(out, [](const plot::Figure& f) { return f.panels.empty(); });
  return out;
}

std::vector<std::pair<std::string, std::string>> fidelityRows(const RunResult& result, const RunSpec& spec) {
  std::vector<std::pair<std::string, std::string>> rows;
  for (std::size_t i = 0; i < result.tracking.size() && i < spec.tracking.size(); ++i) {
    const TrackingFigures& robot = result.tracking[i];
    const TrackingSpec& t = spec.tracking[i];
    std::string when = "every sample";
    if (!t.counts_while.empty()) {
      when = "while the " + (t.scope.empty() ? std::string("default") : t.scope) + " deployment is ";
      for (std::size_t d = 0; d < t.counts_while.size(); ++d) when += (d ? " or " : "") + t.counts_while[d];
    }
    char above[96];
    std::snprintf(above, sizeof above, "%.3f s above 5 mm of %.1f s sampled; largest command step %.3f mm at %.3f s",
                  robot.seconds_above_5mm, robot.seconds_sampled, 1000.0 * robot.max_command_step,
                  robot.max_command_step_at);
    rows.push_back({"worst tracking, " + robot.robot + " (" + when + ")",
                    worstText(robot.position_mm, "mm") + "; " + worstText(robot.orientation_deg, "deg") + "; " + above});
    if (!t.joints.empty())
      rows.push_back({"joints at their velocity limit, " + robot.robot,
                      std::to_string(robot.joint_jumps) + " episodes; fastest " +
                          worstText({100.0 * robot.joint_speed.value, robot.joint_speed.at, robot.joint_speed.state},
                                    "% of the limit")});
  }
  if (spec.clearance.declared) {
    const ClearanceFigures& c = result.clearance;
    char below[128];
    std::snprintf(below, sizeof below, "; %.3f s at or under the threshold of %.1f s counted; %d unmeasurable samples",
                  c.seconds_below, c.seconds_sampled, c.unreachable);
    rows.push_back({"worst clearance (threshold " + millimetres(c.threshold) + ", allowed contacts apart)",
                    std::isinf(c.worst) ? std::string("-")
                                        : millimetres(c.worst) + " at" + seconds(c.worst_at) + " (" + c.worst_state +
                                              ")" + below});
    // Each declared contact on its own row: a contact the task makes on purpose is not a clearance.
    for (const auto& [name, distance] : c.contacts)
      rows.push_back({"allowed contact '" + name + "', smallest distance (0: touching or inside)",
                      std::isinf(distance) ? std::string("-") : millimetres(distance)});
    std::string paused;
    for (const ClearancePause& pause : spec.clearance.pauses) paused += (paused.empty() ? "" : ", ") + pause.name;
    if (!paused.empty()) rows.push_back({"clearance not counted while", paused});
  }
  return rows;
}

std::string executorTimingText(const core::DurationFigures& f) {
  char text[160];
  std::snprintf(text, sizeof text, "median %.1f us, p99 %.1f us, p99.9 %.1f us, worst %.1f us (%llu samples)",
                f.median * 1e6, f.p99 * 1e6, f.p999 * 1e6, f.worst * 1e6, static_cast<unsigned long long>(f.count));
  return text;
}

std::vector<std::pair<std::string, std::string>> executorRows(const ExecutorFigures& e, std::size_t components) {
  std::vector<std::pair<std::string, std::string>> rows;
  if (!e.ran) return rows;
  char head[200];
  std::snprintf(head, sizeof head, "%llu ticks of %.3f ms, %s, memory %s; %llu deadline misses (longest run %llu), %.3f s slipped",
                static_cast<unsigned long long>(e.ticks), e.period * 1e3, e.scheduler.c_str(),
                e.memory_locked ? "locked" : "not locked", static_cast<unsigned long long>(e.deadline_misses),
                static_cast<unsigned long long>(e.worst_consecutive_misses), e.slipped);
  rows.push_back({"executor (wall clock)", head});
  rows.push_back({"executor wake-up latency", executorTimingText(e.wake_latency)});
  rows.push_back({"executor compute per tick", executorTimingText(e.tick_compute)});
  rows.push_back({"executor time per tick outside the steps (switches between instants)", executorTimingText(e.between_steps)});
  if (e.work_between_ticks.count > 0)
    rows.push_back({"executor time per action, fault or input played between ticks", executorTimingText(e.work_between_ticks)});
  // The components whose steps took longest: where a period's budget goes.
  std::vector<const core::ComponentTiming*> slowest;
  for (const core::ComponentTiming& c : e.components) slowest.push_back(&c);
  std::sort(slowest.begin(), slowest.end(), [](const auto* a, const auto* b) { return a->compute.worst > b->compute.worst; });
  if (slowest.size() > components) slowest.resize(components);
  for (const core::ComponentTiming* c : slowest) rows.push_back({"step time, " + c->component, executorTimingText(c->compute)});
  for (const core::HandoverFigures& h : e.handovers) {
    char text[160];
    std::snprintf(text, sizeof text, "oldest %.1f ms (max_age %.1f ms), %llu stale episodes", h.worst_age * 1e3,
                  h.max_age * 1e3, static_cast<unsigned long long>(h.stale));
    rows.push_back({"hand-over age, " + h.component + " (own pace)", text});
  }
  for (const std::string& w : e.warnings) rows.push_back({"executor warning", w});
  return rows;
}

}  // namespace cobra::run
