#include "cobra/run/runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <thread>

#include <lua.hpp>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/deploy/suggest.hpp"
#include "observers.hpp"

namespace cobra::run {
namespace {

/// Plays an action's Lua table (kept in the registry): call, write, set or deployer code.
constexpr const char* kPlayer = R"lua(
return function(f, where)
  local function member(path)
    local name, rest = path:match("^([^.]+)%.(.+)$")
    return rawget(_G, name), rest
  end
  if f.call then
    local c, op = member(f.call)
    return c[op](c, table.unpack(f.args or {}))
  elseif f.write then
    local c, port = member(f.write.port)
    return c[port]:write(f.write.value)
  elseif f.set then
    local c, property = member(f.set.property)
    c[property] = f.set.value
  else
    local chunk, message = load(f.lua, "=" .. where)
    if not chunk then error(message, 0) end
    return chunk()
  end
end
)lua";

/// A chart of `run.charts`: on the lockstep clock its supervisor's active state, read between two
/// instants; in real time its taskState port (the supervisor's thread writes it).
struct Chart {
  const ChartSpec* spec = nullptr;
  const components::Supervisor* supervisor = nullptr;
  std::unique_ptr<Tap<core::TaskState>> state_tap;
  std::string state, previous, shown;  // full path now and one step before; folded as last logged
  std::string last_failure;            // "Source: event at t s"
  bool ended = false;
};

/// An action or fault armed by its trigger.
struct Armed {
  ActionSpec spec;
  bool fault = false;
  double due = -1.0;  // s; < 0: not triggered yet
  int fired = 0;
};

std::string foldState(const std::string& state, const std::vector<std::string>& fold) {
  const auto dot = state.rfind('.');
  if (dot == std::string::npos) return state;
  const std::string leaf = state.substr(dot + 1);
  return std::find(fold.begin(), fold.end(), leaf) != fold.end() ? state.substr(0, dot) : state;
}

bool contains(const std::string& text, const std::vector<std::string>& any) {
  return std::any_of(any.begin(), any.end(), [&](const std::string& s) { return text.find(s) != std::string::npos; });
}

std::vector<std::string> namesOf(const core::ComponentRegistry& refs) {
  std::vector<std::string> names;
  for (const core::Component* c : refs.components()) names.push_back(c->name());
  return names;
}

/// Checks what an action names against the deployment: "file:line: unknown component ...".
void checkAction(const ActionSpec& a, const core::ComponentRegistry& refs, const std::vector<Chart>& charts) {
  const std::string at = a.where.text() + ": ";
  if (a.on.kind == Trigger::Kind::State &&
      std::none_of(charts.begin(), charts.end(), [&](const Chart& c) { return c.spec->name == a.on.chart; })) {
    std::vector<std::string> names;
    for (const Chart& c : charts) names.push_back(c.spec->name);
    throw std::runtime_error(at + "unknown chart '" + a.on.chart + "' in state '" + a.on.chart + ":" + a.on.state +
                             "'" + deploy::suggestionText(a.on.chart, names, "charts (run.charts)"));
  }
  if (a.kind == ActionSpec::Kind::Lua) return;
  core::Component* c = refs.find(a.component);
  if (c == nullptr)
    throw std::runtime_error(at + "unknown component '" + a.component + "' in " + a.text +
                             deploy::suggestionText(a.component, namesOf(refs), "components"));
  std::vector<std::string> known;
  bool found = false;
  std::string one = "operation", many = "operations";
  if (a.kind == ActionSpec::Kind::Call) {
    found = c->findOperation(a.member) != nullptr;
    for (const core::OperationBase* op : c->operations()) known.push_back(op->name());
  } else if (a.kind == ActionSpec::Kind::Write) {
    one = "port", many = "ports";
    found = c->findPort(a.member) != nullptr;
    for (const core::PortBase* p : c->ports()) known.push_back(p->name());
  } else {
    one = "property", many = "properties";
    found = c->findProperty(a.member) != nullptr;
    for (const core::PropertyBase* p : c->properties()) known.push_back(p->name());
  }
  if (!found)
    throw std::runtime_error(at + "component '" + a.component + "' has no " + one + " '" + a.member + "' (" + a.text +
                             ")" + deploy::suggestionText(a.member, known, many));
}

}  // namespace

const char* toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::Completed: return "completed";
    case Outcome::TimeLimit: return "time limit";
    case Outcome::ComponentError: return "component error";
    case Outcome::UnhandledFault: return "fault unhandled";
    case Outcome::SafeStop: return "safe stop";
  }
  return "?";
}

const SummaryValue& RunResult::value(const std::string& name) const {
  for (const SummaryValue& v : summary)
    if (v.name == name) return v;
  throw std::out_of_range("no summary value '" + name + "'");
}

std::filesystem::path entryFile(const std::filesystem::path& app) {
  if (std::filesystem::is_regular_file(app)) return app;
  if (!std::filesystem::is_directory(app)) throw std::runtime_error(app.string() + ": no such file or folder");
  std::filesystem::path folder = app;
  if (folder.filename().empty()) folder = folder.parent_path();  // "apps/x/"
  const std::filesystem::path entry = folder / (folder.filename().string() + ".lua");
  if (!std::filesystem::is_regular_file(entry))
    throw std::runtime_error(folder.string() + ": no entry file " + entry.string() +
                             " (an application folder holds <name>.lua)");
  return entry;
}

RunResult runApp(const RunOptions& options) {
  const std::filesystem::path entry = entryFile(options.app);
  deploy::ConfiguratorOptions configurator_options;
  configurator_options.mode = options.realtime ? deploy::ClockMode::RealTime : deploy::ClockMode::Simulation;
  deploy::Configurator configurator(configurator_options);
  components::addBuiltinPackages(configurator.packages());
  if (options.add_packages) options.add_packages(configurator.packages());
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  if (!options.scenario.empty()) {
    if (!std::filesystem::is_directory(options.scenario))
      throw std::runtime_error("--scenario " + options.scenario.string() + ": no such folder");
    deployer.run("scenario = [[" + options.scenario.string() + "]]", "=scenario");
  }
  if (!options.before_lua.empty()) deployer.run(options.before_lua, "=before_lua");
  deployer.runFile(entry.string());
  if (!options.extra_lua.empty()) deployer.run(options.extra_lua, "=extra_lua");
  deployer.run("getReferences()", "=run");
  const RunSpec spec = readRunSpec(lua.get(), entry.string());
  core::ComponentRegistry& refs = configurator.getReferences();
  const std::string run_where = entry.string();

  // The charts, through their supervisors' taskState ports.
  std::vector<Chart> charts;
  for (const ChartSpec& c : spec.charts) {
    Chart chart;
    chart.spec = &c;
    chart.state_tap = std::make_unique<Tap<core::TaskState>>(refs, c.supervisor + ".taskState", c.where.text(),
                                                             "run.charts '" + c.name + "'",
                                                             "a Supervisor's taskState (TaskState)");
    chart.supervisor = dynamic_cast<const components::Supervisor*>(refs.find(c.supervisor));
    if (chart.supervisor == nullptr)
      throw std::runtime_error(c.where.text() + ": run.charts '" + c.name + "': component '" + c.supervisor +
                               "' is not a Supervisor");
    if (!options.realtime) chart.state = chart.supervisor->activeState();
    charts.push_back(std::move(chart));
  }
  auto chartOf = [&](const std::string& name) -> Chart* {
    for (Chart& c : charts)
      if (c.spec->name == name) return &c;
    return nullptr;
  };
  // Which chart receives a source's events (the first chart unless one lists the source).
  auto chartForSource = [&](const std::string& source) -> Chart& {
    for (Chart& c : charts)
      for (const std::string& prefix : c.spec->sources)
        if (source.rfind(prefix, 0) == 0) return c;
    return charts.front();
  };

  // Actions of the app and faults of the faults file, checked against the deployment.
  std::vector<Armed> armed;
  for (const ActionSpec& a : spec.actions) armed.push_back({a, false});
  std::filesystem::path faults_file = options.faults_file;
  if (faults_file.empty() && !options.scenario.empty() && std::filesystem::exists(options.scenario / "faults.lua"))
    faults_file = options.scenario / "faults.lua";
  if (!faults_file.empty()) {
    if (!std::filesystem::is_regular_file(faults_file))
      throw std::runtime_error("--faults " + faults_file.string() + ": no such file");
    for (ActionSpec& a : readFaults(lua.get(), faults_file.string())) armed.push_back({std::move(a), true});
  }
  for (const Armed& a : armed) checkAction(a.spec, refs, charts);
  lua.run(std::string("cobra_run_play = (function() ") + kPlayer + " end)()", "=cobra run");

  // Event log: every component's events and every supervisor's outputEvents.
  std::vector<std::pair<std::string, std::unique_ptr<core::InputPortBase>>> event_taps;
  for (const core::Component* c : refs.components())
    for (const char* port : {"events", "outputEvents"}) {
      auto* out = dynamic_cast<core::OutputPortBase*>(c->findPort(port));
      if (out == nullptr) continue;
      auto reader = out->makeReader(c->name() + "_" + port, "cobra run event log");
      out->connectTo(*reader, core::ConnPolicy::buffer(256));
      event_taps.emplace_back(c->name(), std::move(reader));
    }

  // Recorded columns: the record list, the plots' ports, the derived figures.
  Recording recording;
  for (const auto& [port, where] : spec.record.ports) recording.addPort(refs, port, where.text(), "run.record");
  std::vector<Tracker> trackers;
  for (const TrackingSpec& t : spec.tracking) {
    Tracker tracker;
    tracker.spec = t;
    const std::string use = "run.tracking '" + t.name + "'";
    tracker.commanded = std::make_unique<Tap<KDL::Frame>>(refs, t.commanded, t.where.text(), use, "KDL.Frame");
    tracker.measured = std::make_unique<Tap<KDL::Frame>>(refs, t.measured, t.where.text(), use, "KDL.Frame");
    std::vector<double> limits;
    if (!t.joints.empty()) {
      tracker.joints = std::make_unique<Tap<KDL::JntArray>>(refs, t.joints, t.where.text(), use, "KDL.JntArray");
      const auto dot = t.max_velocity.find('.');
      core::Component* owner = refs.find(t.max_velocity.substr(0, dot));
      if (dot == std::string::npos || owner == nullptr || owner->findProperty(t.max_velocity.substr(dot + 1)) == nullptr)
        throw std::runtime_error(t.where.text() + ": " + use + ": max_velocity '" + t.max_velocity +
                                 "' is not a property Comp.name of the deployment");
      limits = owner->getProperty<std::vector<double>>(t.max_velocity.substr(dot + 1));
      if (limits.empty())
        throw std::runtime_error(t.where.text() + ": " + use + ": " + t.max_velocity +
                                 " is empty: the joint-jump check needs the joints' velocity limits (rad/s, m/s)");
    }
    if (!t.chart.empty() && chartOf(t.chart) == nullptr)
      throw std::runtime_error(t.where.text() + ": " + use + ": unknown chart '" + t.chart + "'");
    tracker.monitor = std::make_unique<TrackingMonitor>(t.name, limits, spec.step);
    tracker.mm_column = recording.addDerived("tracking." + t.name + ".mm", "mm");
    tracker.deg_column = recording.addDerived("tracking." + t.name + ".deg", "deg");
    trackers.push_back(std::move(tracker));
  }
  std::vector<std::size_t> accept_columns;  // pairs per tracker: mm, deg
  for (const Tracker& t : trackers) {
    accept_columns.push_back(recording.addDerived("tracking." + t.spec.name + ".accept_mm", "mm"));
    accept_columns.push_back(recording.addDerived("tracking." + t.spec.name + ".accept_deg", "deg"));
  }
  std::unique_ptr<ClearanceObserver> clearance;
  RunResult result;
  if (spec.clearance.declared) {
    clearance = std::make_unique<ClearanceObserver>();
    clearance->spec = spec.clearance;
    const std::string at = spec.clearance.where.text();
    clearance->clearance = std::make_unique<Tap<double>>(refs, spec.clearance.port, at, "run.clearance", "double (m)");
    for (const auto& [name, port] : spec.clearance.contacts) {
      clearance->contacts.push_back(std::make_unique<Tap<double>>(refs, port, at, "run.clearance contact '" + name + "'",
                                                                  "double (m)"));
      clearance->contact_columns.push_back(recording.addDerived("contact." + name, "m"));
      result.clearance.contacts.emplace_back(name, std::numeric_limits<double>::infinity());
    }
    for (const ClearancePause& pause : spec.clearance.pauses)
      if (chartOf(pause.chart) == nullptr)
        throw std::runtime_error(at + ": run.clearance pause '" + pause.name + "': unknown chart '" + pause.chart + "'");
    clearance->paused.assign(spec.clearance.pauses.size(), false);
    double threshold = spec.clearance.threshold;
    if (!spec.clearance.threshold_operation.empty()) {
      const std::string& op = spec.clearance.threshold_operation;
      const auto dot = op.find('.');
      core::Component* owner = refs.find(op.substr(0, dot));
      if (dot == std::string::npos || owner == nullptr || owner->findOperation(op.substr(dot + 1)) == nullptr)
        throw std::runtime_error(at + ": run.clearance: threshold '" + op + "' is not an operation Comp.name");
      threshold = owner->call<double>(op.substr(dot + 1));
    }
    result.clearance.threshold = threshold;
    clearance->column = recording.addDerived("clearance", "m");
    clearance->threshold_column = recording.addDerived("clearance.threshold", "m");
  }
  // The plots' series: ports are recorded too; every name must be a column.
  for (const PlotSpec& p : spec.plots) {
    std::vector<std::string> names = p.series;
    if (!p.x.empty()) names.push_back(p.x);
    for (const std::string& name : names) {
      std::vector<std::string> fields;
      const bool derived = name.rfind("tracking.", 0) == 0 || name.rfind("clearance", 0) == 0 ||
                           name.rfind("contact.", 0) == 0;
      if (!derived) {
        const auto end = name.find_first_of(".[", name.find('.') + 1);
        recording.addPort(refs, name.substr(0, end), p.where.text(), "run.plots '" + p.title + "'");
      }
      if (recording.knows(name, fields)) continue;
      std::string known;
      if (!fields.empty()) {
        for (const std::string& f : fields) known += (known.empty() ? "" : ", ") + name + (f[0] == '[' ? "" : ".") + f;
        throw std::runtime_error(p.where.text() + ": run.plots '" + p.title + "': " + name +
                                 " has several values; name one: " + known);
      }
      throw std::runtime_error(p.where.text() + ": run.plots '" + p.title + "': no column '" + name + "'" +
                               deploy::suggestionText(name, recording.columnNames(), "columns"));
    }
  }
  std::vector<SummaryObserver> summaries;
  for (const SummarySpec& s : spec.summary) {
    SummaryObserver o;
    o.spec = s;
    const std::string use = "run.summary '" + s.name + "'";
    if (s.kind == SummarySpec::Kind::Distance)
      for (const std::string& port : s.ports)
        o.frames.push_back(std::make_unique<Tap<KDL::Frame>>(refs, port, s.where.text(), use, "KDL.Frame"));
    if (s.kind == SummarySpec::Kind::Port)
      o.value = std::make_unique<Tap<double>>(refs, s.ports[0], s.where.text(), use, "double");
    if (s.kind != SummarySpec::Kind::Count && chartOf(s.chart) == nullptr)
      throw std::runtime_error(s.where.text() + ": " + use + ": unknown chart '" + s.chart + "'");
    summaries.push_back(std::move(o));
    result.summary.push_back({s.name, s.unit, {}, {}, {}});
  }

  // Every scope a chart switches, and the configuration, as the timeline and the log show them.
  std::vector<std::string> scopes;
  for (const ChartSpec& c : spec.charts)
    if (std::find(scopes.begin(), scopes.end(), c.scope) == scopes.end()) scopes.push_back(c.scope);
  std::vector<std::string> shown_deployment(scopes.size());
  std::string shown_configuration;
  std::vector<core::Component*> components = refs.components();

  report::TimelineRecorder timeline;
  auto say = [&](double t, const std::string& what) {
    if (options.progress) options.progress(seconds(t) + "  " + what);
  };
  auto statesText = [&] {
    std::string text;
    for (const Chart& c : charts) text += (text.empty() ? "" : ", ") + c.spec->name + " " + c.state;
    return text;
  };
  const auto start_wall = std::chrono::steady_clock::now();
  if (!options.realtime) configurator.clock().setStepObserver(options.step_observer);
  const auto step = std::chrono::duration<double>(spec.step);
  const long record_every = std::max(1L, std::lround(spec.record.period / spec.step));
  double next_progress = options.progress_every;
  double safe_stop_at = -1.0;
  bool stopped = false;
  long steps = 0;
  double t = 0.0;
  while (!stopped) {
    if (options.realtime) {
      std::this_thread::sleep_for(std::chrono::duration_cast<std::chrono::nanoseconds>(step));
      t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_wall).count();
    } else {
      configurator.clock().advance(std::chrono::duration_cast<std::chrono::nanoseconds>(step));
      t = std::chrono::duration<double>(configurator.clock().now()).count();
    }
    ++steps;
    core::TaskState task_state;
    for (Chart& c : charts) {
      c.previous = c.state;
      if (options.realtime && c.state_tap->read(task_state)) c.state = task_state.path.str();
      if (!options.realtime) c.state = c.supervisor->activeState();
    }
    for (auto& [source, reader] : event_taps) {
      std::string text;
      while (reader->readText(text) == core::FlowStatus::NewData) {
        Chart& chart = chartForSource(source);
        result.events.push_back({t, source, text, chart.state});
        const std::string event = text.substr(0, text.find(' '));
        result.log.push_back(source + ": " + event);
        if (std::find(spec.failures.begin(), spec.failures.end(), event) != spec.failures.end())
          chart.last_failure = source + ": " + event + " at" + seconds(t);
        for (Armed& a : armed)
          if (a.due < 0.0 && (a.spec.repeat || a.fired == 0) && a.spec.on.kind == Trigger::Kind::Event &&
              a.spec.on.event == event && (a.spec.on.source.empty() || a.spec.on.source == source))
            a.due = t + a.spec.after;
      }
    }
    for (Chart& c : charts) {
      const std::string folded = foldState(c.state, spec.fold);
      timeline.observe(t, c.spec->name + " chart", folded.empty() ? "(none)" : folded);
      if (folded != c.shown) {
        c.shown = folded;
        say(t, c.spec->name + " > " + folded);
        result.log.push_back(c.spec->name + " > " + folded);
      }
    }
    bool switched = false;
    for (std::size_t s = 0; s < scopes.size(); ++s) {
      const std::string& now = configurator.currentDeployment(scopes[s]);
      if (now == shown_deployment[s]) continue;
      shown_deployment[s] = now;
      switched = true;
      const std::string lane = (scopes[s].empty() ? std::string() : scopes[s] + " ") + "deployment";
      timeline.observe(t, lane, now.empty() ? "(none)" : now);
      result.switches.push_back(seconds(t) + " " + lane + " " + now);
      result.log.push_back(lane + " > " + now);
      say(t, "  " + lane + " -> " + now);
    }
    if (configurator.currentConfiguration() != shown_configuration) {
      shown_configuration = configurator.currentConfiguration();
      timeline.observe(t, "configuration", shown_configuration);
      result.switches.push_back(seconds(t) + " configuration " + shown_configuration);
      result.log.push_back("configuration > " + shown_configuration);
      say(t, "  configuration -> " + shown_configuration);
    }
    if (switched) components = refs.components();

    // Summary values sampled at a chart's state entry or exit.
    for (std::size_t i = 0; i < summaries.size(); ++i) {
      const SummarySpec& s = summaries[i].spec;
      if (s.kind == SummarySpec::Kind::Count) continue;
      const Chart& c = *chartOf(s.chart);
      const bool in = c.state.rfind(s.state, 0) == 0, was = c.previous.rfind(s.state, 0) == 0;
      if (s.leave ? !(was && !in) : !(in && !was)) continue;
      double value = NAN;
      KDL::Frame a, b;
      if (s.kind == SummarySpec::Kind::Distance && summaries[i].frames[0]->read(a) && summaries[i].frames[1]->read(b))
        value = s.scale * (a.p - b.p).Norm();
      if (s.kind == SummarySpec::Kind::Port && summaries[i].value->read(value)) value *= s.scale;
      if (std::isnan(value)) continue;
      result.summary[i].values.push_back(value);
      result.summary[i].times.push_back(t);
      if (s.say) say(t, "  " + s.name + ": " + std::to_string(value).substr(0, 5) + " " + s.unit);
    }
    // Actions and faults: armed by their trigger, played `after` s later.
    for (Armed& a : armed) {
      if (a.due < 0.0 && (a.spec.repeat || a.fired == 0)) {
        if (a.spec.on.kind == Trigger::Kind::Time && a.fired == 0 && t + 1e-9 >= a.spec.on.time) a.due = t + a.spec.after;
        if (a.spec.on.kind == Trigger::Kind::State) {
          const Chart& c = *chartOf(a.spec.on.chart);
          if (c.state.rfind(a.spec.on.state, 0) == 0 && c.previous.rfind(a.spec.on.state, 0) != 0) a.due = t + a.spec.after;
        }
      }
      if (a.due < 0.0 || t + 1e-9 < a.due) continue;
      a.due = -1.0;
      ++a.fired;
      const std::string label = std::string(a.fault ? "fault " : "action ") + a.spec.where.text();
      say(t, "  " + label + ": " + a.spec.text);
      result.log.push_back(label);
      lua_State* L = lua.get();
      lua_getglobal(L, "cobra_run_play");
      lua_rawgeti(L, LUA_REGISTRYINDEX, a.spec.lua_ref);
      lua_pushstring(L, a.spec.where.text().c_str());
      if (lua_pcall(L, 2, 0, 0) != LUA_OK) {
        const std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(no message)";
        lua_pop(L, 1);
        throw std::runtime_error(a.spec.where.text() + ": " + a.spec.text + " failed at" + seconds(t) + ": " + message);
      }
    }

    // Fidelity: tracking every step, the clearance's newest value.
    for (std::size_t i = 0; i < trackers.size(); ++i) {
      Tracker& tr = trackers[i];
      KDL::Frame commanded, measured;
      KDL::JntArray q;
      if (!tr.commanded->read(commanded) || !tr.measured->read(measured)) continue;
      const bool have_q = tr.joints && tr.joints->read(q);
      const bool counts =
          tr.spec.counts_while.empty() ||
          std::find(tr.spec.counts_while.begin(), tr.spec.counts_while.end(),
                    configurator.currentDeployment(tr.spec.scope)) != tr.spec.counts_while.end();
      const Chart* c = tr.spec.chart.empty() ? nullptr : chartOf(tr.spec.chart);
      tr.monitor->step(t, counts, c ? c->state : std::string(), commanded, measured, have_q ? &q : nullptr);
    }
    if (clearance) {
      ClearanceFigures& figures = result.clearance;
      for (std::size_t p = 0; p < clearance->spec.pauses.size(); ++p) {
        const ClearancePause& pause = clearance->spec.pauses[p];
        const std::string& state = chartOf(pause.chart)->state;
        if (contains(state, pause.from)) clearance->paused[p] = true;
        else if (contains(state, pause.to)) clearance->paused[p] = false;
      }
      double d = NAN;
      const bool counts = std::none_of(clearance->paused.begin(), clearance->paused.end(), [](bool b) { return b; });
      if (clearance->clearance->read(d) && counts) {
        clearance->last = d;
        figures.seconds_sampled += spec.step;
        if (std::isnan(d)) {
          ++figures.unreachable;
        } else {
          if (d <= figures.threshold) figures.seconds_below += spec.step;
          if (d < figures.worst) figures.worst = d, figures.worst_at = t, figures.worst_state = statesText();
        }
      } else if (!counts) {
        clearance->last = NAN;
      }
      for (std::size_t k = 0; k < clearance->contacts.size(); ++k) {
        double contact = NAN;
        if (clearance->contacts[k]->read(contact) && !std::isnan(contact)) {
          figures.contacts[k].second = std::min(figures.contacts[k].second, contact);
          recording.set(clearance->contact_columns[k], contact);
        }
      }
    }
    if (steps % record_every == 0) {
      for (std::size_t i = 0; i < trackers.size(); ++i) {
        const auto [mm, deg] = trackers[i].monitor->takeWindowMaximum();
        recording.set(trackers[i].mm_column, mm);
        recording.set(trackers[i].deg_column, deg);
        recording.set(accept_columns[2 * i], trackers[i].spec.accept_mm);
        recording.set(accept_columns[2 * i + 1], trackers[i].spec.accept_deg);
      }
      if (clearance) {
        recording.set(clearance->column, clearance->last);
        recording.set(clearance->threshold_column, result.clearance.threshold);
      }
      recording.sample(t);
    }

    // How the run ends: the charts done, a safe stop, a component in error, the time limit.
    for (Chart& c : charts) {
      if (c.spec->safe_stop.empty() || c.state != c.spec->safe_stop || c.previous == c.spec->safe_stop) continue;
      result.log.push_back(c.spec->name + " safe stop");
      if (result.outcome == Outcome::SafeStop) continue;
      result.outcome = Outcome::SafeStop;
      safe_stop_at = t;
      const std::string before = foldState(c.previous, spec.fold);
      result.reason = c.spec->name + " chart stopped safely in " + before + ": " +
                      (c.last_failure.empty() ? "(no failure event seen)" : c.last_failure) +
                      (spec.safe_stop_reason.empty() ? "" : ", " + spec.safe_stop_reason);
      const std::string source = c.last_failure.substr(0, c.last_failure.find(':'));
      const std::string event = c.last_failure.empty() ? "" : c.last_failure.substr(source.size() + 2,
                                                                                    c.last_failure.find(" at") - source.size() - 2);
      const auto why = spec.explain.find(event);
      if (why != spec.explain.end() && refs.find(source) && refs.get(source).findOperation(why->second))
        result.reason += "; " + source + "." + why->second + "(): " + refs.get(source).call<std::string>(why->second);
      say(t, "SAFE STOP: " + result.reason);
    }
    for (const core::Component* c : components) {
      const core::State s = c->state();
      if (s != core::State::Exception && s != core::State::FatalError) continue;
      result.outcome = Outcome::ComponentError;
      result.reason = "component '" + c->name() + "' is in " + std::string(core::toString(s)) + ": " + c->lastError();
      stopped = true;
      break;
    }
    if (stopped) break;
    const bool all_done = std::all_of(charts.begin(), charts.end(), [](const Chart& c) { return c.state == c.spec->done; });
    if (all_done) {
      result.outcome = Outcome::Completed;
      result.reason.clear();
      break;
    }
    if (result.outcome == Outcome::SafeStop) {
      const bool ended = std::all_of(charts.begin(), charts.end(), [](const Chart& c) {
        return c.state == c.spec->done || c.state == c.spec->safe_stop;
      });
      if (ended || t - safe_stop_at >= spec.safe_stop_linger) break;
    }
    if (t >= options.time_limit - 1e-9) {
      const auto fault = std::find_if(armed.begin(), armed.end(), [](const Armed& a) { return a.fault && a.fired > 0; });
      char limit[64];
      std::snprintf(limit, sizeof limit, "time limit %.3f s reached", options.time_limit);
      if (fault != armed.end()) {
        result.outcome = Outcome::UnhandledFault;
        result.reason = std::string(limit) + " after fault " + fault->spec.where.text() + " (" + fault->spec.text +
                        "): the task did not recover; charts: " + statesText();
      } else {
        result.outcome = Outcome::TimeLimit;
        result.reason = std::string(limit) + "; charts: " + statesText();
      }
      break;
    }
    if (t >= next_progress) {
      next_progress += options.progress_every;
      say(t, "running; " + statesText());
    }
  }
  result.duration = t;
  for (const Chart& c : charts) result.states_entered[c.spec->name] = timeline.statesEntered(c.spec->name + " chart");
  for (const Tracker& tr : trackers) result.tracking.push_back(tr.monitor->figures());
  for (std::size_t i = 0; i < summaries.size(); ++i) {
    SummaryValue& v = result.summary[i];
    const SummarySpec& s = summaries[i].spec;
    if (s.kind == SummarySpec::Kind::Count) {
      for (const report::EventRecord& e : result.events)
        if (std::find(s.events.begin(), s.events.end(), e.event.substr(0, e.event.find(' '))) != s.events.end())
          v.values.push_back(1.0), v.times.push_back(e.time);
      v.text = std::to_string(v.values.size());
      continue;
    }
    char number[32];
    for (const double value : v.values) {
      std::snprintf(number, sizeof number, "%.2f", value);
      v.text += (v.text.empty() ? "" : ", ") + std::string(number) + (s.unit.empty() ? "" : " " + s.unit);
    }
    if (v.text.empty()) v.text = "-";
    if (!s.of.empty()) {
      const auto dot = s.of.find('.');
      core::Component* owner = refs.find(s.of.substr(0, dot));
      if (dot != std::string::npos && owner != nullptr && owner->findOperation(s.of.substr(dot + 1)) != nullptr)
        v.text += " (" + std::to_string(v.values.size()) + " of " +
                  std::to_string(owner->call<int>(s.of.substr(dot + 1))) + ")";
    }
  }
  say(t, std::string("run ended: ") + toString(result.outcome) + (result.reason.empty() ? "" : ": " + result.reason));

  if (!options.report_folder.empty()) {
    report::RunReport run;
    run.title = spec.title + (options.scenario.empty() ? "" : ": " + options.scenario.filename().string());
    run.summary = {{"application", entry.string()},
                   {"result", std::string(toString(result.outcome)) + (result.reason.empty() ? "" : ": " + result.reason)},
                   {"duration", seconds(result.duration)},
                   {"deployment/configuration switches", std::to_string(result.switches.size())}};
    if (!options.scenario.empty()) run.summary.insert(run.summary.begin() + 1, {"scenario", options.scenario.string()});
    for (const SummaryValue& v : result.summary) run.summary.emplace_back(v.name, v.text);
    for (auto& row : fidelityRows(result, spec)) run.summary.push_back(std::move(row));
    run.events = result.events;
    run.timeline = timeline.intervals(result.duration);
    run.figures = reportFigures(spec, recording, trackers, clearance.get());
    run.files = {"signals.csv"};
    result.report = report::writeRunFolder(options.report_folder, run);
    const std::filesystem::path signals = options.report_folder / "signals.csv";
    std::ofstream csv(signals);
    csv << recording.csv();
    if (!csv) throw std::runtime_error("cobra run: cannot write " + signals.string());
  }
  return result;
}

}  // namespace cobra::run
