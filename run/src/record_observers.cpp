// The observers `record` (ports recorded every period into signals.csv) and `plots` (the
// report's figures of recorded columns), with the figure helpers the other observers share.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <lua.hpp>

#include "builtin_observers.hpp"
#include "cobra/deploy/suggest.hpp"
#include "lua_reader.hpp"

namespace cobra::run {
namespace {

using detail::Reader;

// When chart `chart` first entered a state whose path starts with `state` (s; nullopt: never).
std::optional<double> firstEntered(const std::vector<StateInterval>& timeline, const std::string& chart,
                                   const std::string& state) {
  const std::string lane = chart + " chart";
  const auto entered = std::find_if(timeline.begin(), timeline.end(), [&](const StateInterval& interval) {
    return interval.chart == lane && interval.state.rfind(state, 0) == 0;
  });
  if (entered == timeline.end()) return std::nullopt;
  return entered->begin;
}

// Column `y` against column `x` at their common sample times from `from` s on, the marks placed on it.
Series pathSeries(const Recording& recording, const PathSpec& path, const std::vector<StateInterval>& timeline,
                  double from) {
  Series s{path.label, {}, {}, path.dashed};
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

// A path's `marks = { { "A", "chart:state path" }, ... }`.
std::vector<PathSpec::Mark> readMarks(const Reader& entry) {
  std::vector<PathSpec::Mark> marks;
  lua_State* L = entry.state();
  lua_getfield(L, -1, "marks");
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    return marks;
  }
  // Pops the marks table before failing, as the Reader's own checks do.
  const auto bad = [&](const std::string& what) {
    lua_pop(L, 1);
    entry.fail("`marks` " + what + "; write marks = { { \"A\", \"chart:state path\" }, ... }");
  };
  if (!lua_istable(L, -1)) bad("must be a list");
  const lua_Integer n = luaL_len(L, -1);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    std::string pair[2];
    bool ok = lua_istable(L, -1) && luaL_len(L, -1) == 2;
    for (int k = 0; ok && k < 2; ++k) {
      lua_rawgeti(L, -1, k + 1);
      ok = lua_type(L, -1) == LUA_TSTRING;
      if (ok) pair[k] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    if (!ok) bad("entry " + std::to_string(i) + " is not a pair of strings");
    PathSpec::Mark mark;
    mark.label = pair[0];
    std::tie(mark.chart, mark.state) = detail::chartState(entry, pair[1]);
    marks.push_back(std::move(mark));
  }
  lua_pop(L, 1);
  return marks;
}

// `run.record`: its ports are columns of signals.csv from the first row.
class RecordObserver final : public Observer {
 public:
  void attach(ObserverContext& run) override {
    for (const auto& [port, where] : run.spec.record.ports) run.recording.addPort(run.components, port, where.text(), "run.record");
  }
};

// `run.plots`: the figures of the report. A plot's ports are recorded too; every name it gives
// must be a column (checked once every observer added its own).
class PlotsObserver final : public Observer {
 public:
  void attach(ObserverContext& run) override {
    spec_ = &run.spec;
    for (const PlotSpec& p : run.spec.plots) {
      const std::string use = "run.plots '" + p.title + "'";
      if (!p.from_chart.empty() && run.chart(p.from_chart) == nullptr)
        throw std::runtime_error(p.where.text() + ": " + use + ": from: no chart '" + p.from_chart + "' in run.charts");
      for (const PathSpec& path : p.paths)
        for (const PathSpec::Mark& mark : path.marks)
          if (run.chart(mark.chart) == nullptr)
            throw std::runtime_error(p.where.text() + ": " + use + ": path '" + path.label + "', mark '" + mark.label +
                                     "': no chart '" + mark.chart + "' in run.charts");
    }
  }
  void attached(ObserverContext& run) override {
    for (const PlotSpec& p : run.spec.plots) {
      std::vector<std::string> names = p.series;
      if (!p.x.empty()) names.push_back(p.x);
      for (const PathSpec& path : p.paths) names.push_back(path.x), names.push_back(path.y);
      const std::string use = "run.plots '" + p.title + "'";
      for (const std::string& name : names) {
        const bool derived = startsWith(name, "tracking.") || startsWith(name, "clearance") || startsWith(name, "contact.");
        if (!derived)
          run.recording.addPort(run.components, name.substr(0, name.find_first_of(".[", name.find('.') + 1)),
                                p.where.text(), use);
        std::vector<std::string> fields;
        if (run.recording.knows(name, fields)) continue;
        if (fields.empty())
          throw std::runtime_error(p.where.text() + ": " + use + ": no column '" + name + "'" +
                                   deploy::suggestionText(name, run.recording.columnNames(), "columns"));
        std::string known;
        for (const std::string& f : fields) known += (known.empty() ? "" : ", ") + name + (f[0] == '[' ? "" : ".") + f;
        throw std::runtime_error(p.where.text() + ": " + use + ": " + name + " has several values; name one: " + known);
      }
    }
  }
  void report(RunReport& report, const Recording& recording) const override {
    std::vector<Figure> figures = plotFigures(spec_->plots, recording, report.timeline);
    for (Figure& f : figures) report.figures.push_back(std::move(f));
  }

 private:
  const RunSpec* spec_ = nullptr;
};

}  // namespace

std::vector<Figure> plotFigures(const std::vector<PlotSpec>& plots, const Recording& recording,
                                const std::vector<StateInterval>& timeline) {
  std::vector<Figure> out;
  for (const PlotSpec& p : plots) {
    if (!p.paths.empty()) {
      Panel paths{p.title, p.paths.front().x + (p.x_unit.empty() ? "" : " [" + p.x_unit + "]"),
                  p.paths.front().y + (p.unit.empty() ? "" : " [" + p.unit + "]"), {}};
      double from = 0.0;
      if (!p.from_chart.empty()) from = firstEntered(timeline, p.from_chart, p.from_state).value_or(INFINITY);
      for (const PathSpec& path : p.paths) {
        Series s = pathSeries(recording, path, timeline, from);
        if (!s.x.empty()) paths.series.push_back(std::move(s));
      }
      out.push_back({p.title, {std::move(paths)}});
      continue;
    }
    Panel one{p.title, p.x.empty() ? "t [s]" : p.x + (p.x_unit.empty() ? "" : " [" + p.x_unit + "]"),
              p.unit.empty() ? "value" : "[" + p.unit + "]", {}};
    for (const std::string& name : p.series) {
      Series s{name, {}, {}};
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
  dropEmpty(out);
  return out;
}

void dropEmpty(std::vector<Figure>& figures) {
  for (Figure& f : figures) std::erase_if(f.panels, [](const Panel& p) { return p.series.empty(); });
  std::erase_if(figures, [](const Figure& f) { return f.panels.empty(); });
}

ObserverRegistry::Kind recordObserver() {
  return {"record", "ports recorded every `period` s into signals.csv (run/README.md)", "cobra",
          [](const Section& section) -> std::unique_ptr<Observer> {
            const Reader& record = section.reader();
            if (!lua_istable(record.state(), -1)) record.fail("must be a table");
            RecordSpec& spec = section.spec().record;
            spec.period = record.number("period", spec.period, true);
            for (const std::string& port : record.strings("ports"))
              spec.ports.emplace_back(port, Where{record.where().file, record.lineOf(port)});
            return std::make_unique<RecordObserver>();
          }};
}

ObserverRegistry::Kind plotsObserver() {
  return {"plots", "figures of the report: recorded columns against time or another column, or paths",
          "cobra", [](const Section& section) -> std::unique_ptr<Observer> {
            std::vector<PlotSpec>& plots = section.spec().plots;
            section.reader().items(
                [&](Reader& p) {
                  PlotSpec plot;
                  plot.title = p.string("title", true);
                  plot.unit = p.string("unit", false);
                  plot.x = p.string("x", false);
                  plot.x_unit = p.string("x_unit", false);
                  plot.series = p.strings("series");
                  p.list(
                      "paths",
                      [&](Reader& entry) {
                        PathSpec path;
                        path.label = entry.string("label", true);
                        path.x = entry.string("x", true);
                        path.y = entry.string("y", true);
                        path.dashed = entry.boolean("dashed", false);
                        path.marks = readMarks(entry);
                        plot.paths.push_back(std::move(path));
                      },
                      "label");
                  if (plot.series.empty() == plot.paths.empty())
                    p.fail("needs either `series = { \"Comp.port\", ... }` or `paths = { { label = , x = , y = }, ... }`");
                  if (!plot.paths.empty() && !plot.x.empty())
                    p.fail("`x` is for series; each path names its own x and y columns");
                  if (p.has("from")) {
                    if (plot.paths.empty()) p.fail("`from` is for paths");
                    std::tie(plot.from_chart, plot.from_state) = detail::chartState(p, p.string("from", true));
                  }
                  plot.where = p.where();
                  plots.push_back(std::move(plot));
                },
                "title");
            return std::make_unique<PlotsObserver>();
          }};
}

}  // namespace cobra::run
