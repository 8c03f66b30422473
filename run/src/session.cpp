#include "session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <thread>

#include <lua.hpp>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/fault_injection.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "action_check.hpp"
#include "cobra/deploy/suggest.hpp"
#include "cobra/statechart/description.hpp"

namespace cobra::run {
namespace {

// Plays an action's Lua table (kept in the registry): call, write, set or deployer code.
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

deploy::ConfiguratorOptions configuratorOptions(const RunOptions& run) {
  deploy::ConfiguratorOptions options;
  options.mode = !run.realtime              ? deploy::ClockMode::Simulation
                 : run.thread_per_component ? deploy::ClockMode::RealTime
                                            : deploy::ClockMode::WallClock;
  options.host = run.host;
  return options;
}



/// The report folder is written at the run's end: a folder that cannot be written is refused
/// before anything is loaded, not after a whole procedure. Made if missing, then written to
/// (a probe file, removed): what the end will do.
void checkReportFolder(const std::filesystem::path& folder) {
  if (folder.empty()) return;
  const auto refuse = [&](const std::string& why) {
    throw std::runtime_error("--report " + folder.string() + ": " + why +
                             "; give a folder that can be written (it is made if missing)");
  };
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) refuse("cannot create the folder (" + error.message() + ")");
  if (!std::filesystem::is_directory(folder)) refuse("not a folder");
  const std::filesystem::path probe = folder / ".cobra_write_check";
  {
    std::ofstream out(probe, std::ios::binary);
    out << "x";
    if (!out) refuse("cannot write a file there");
  }
  std::filesystem::remove(probe, error);
}

}  // namespace

std::string foldState(const std::string& state, const std::vector<std::string>& fold) {
  const auto dot = state.rfind('.');
  if (dot == std::string::npos) return state;
  const std::string leaf = state.substr(dot + 1);
  return std::find(fold.begin(), fold.end(), leaf) != fold.end() ? state.substr(0, dot) : state;
}

Session::Session(const RunOptions& options, std::filesystem::path entry)
    : options_(options),
      entry_(std::move(entry)),
      configurator_(configuratorOptions(options)),
      deployer_(configurator_, lua_),
      refs_(configurator_.getReferences()) {
  // On the wall clock the executor locks the process's memory when it starts; locking all that a
  // loaded deployment has mapped stalls the process's threads for longer than a DDS link's lease
  // to its peer hosts (0.1 s: the peers then lost each other at the start). Locked before the
  // files run, memory is locked as it is mapped, and the executor's lock finds it done. Undone
  // below when the files do not lock memory (setExecutor's lock_memory). Best effort: the
  // executor reports a refused lock.
  checkReportFolder(options_.report_folder);
  const bool locked_early = configurator_.mode() == deploy::ClockMode::WallClock && mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
  components::addBuiltinPackages(configurator_.packages());
  if (options_.add_packages) options_.add_packages(configurator_.packages());
  if (!options_.scenario.empty()) {
    if (!std::filesystem::is_directory(options_.scenario))
      throw std::runtime_error("--scenario " + options_.scenario.string() + ": no such folder");
    deployer_.run("scenario = [[" + options_.scenario.string() + "]]", "=scenario");
  }
  if (options_.interactive) deployer_.run("interactive = true", "=interactive");
  // The files may choose what differs on the wall clock (a DDS link's lease, say): `realtime`.
  if (options_.realtime) deployer_.run("realtime = true", "=realtime");
  if (!options_.before_lua.empty()) deployer_.run(options_.before_lua, "=before_lua");
  deployer_.runFile(entry_.string());
  if (!options_.extra_lua.empty()) deployer_.run(options_.extra_lua, "=extra_lua");
  if (locked_early && !configurator_.executorOptions().lock_memory) munlockall();
  deployer_.run("getReferences()", "=run");
  spec_ = readRunSpec(lua_.get(), entry_.string());
  dropOtherHostsEntries();
  attachCharts();
  armActions();
  attachEventLog();
  attachObservers();
  for (const ChartSpec& c : spec_.charts)
    if (std::find(scopes_.begin(), scopes_.end(), c.scope) == scopes_.end()) scopes_.push_back(c.scope);
  shown_deployment_.resize(scopes_.size());
  scope_configuration_.resize(scopes_.size());
  timeline_configuration_.resize(scopes_.size());
  if (!options_.realtime)
    for (const core::Component* c : refs_.components())
      if (const auto* supervisor = dynamic_cast<const components::Supervisor*>(c)) switchers_.emplace_back(supervisor, "");
  components_ = refs_.components();
  listenToComponents();
  record_every_ = std::max(1L, std::lround(spec_.record.period / spec_.step));
  next_progress_ = options_.progress_every;
  if (!options_.realtime) configurator_.clock().setStepObserver(options_.step_observer);
  if (options_.observer != nullptr) attachObserver();
  if (configurator_.mode() == deploy::ClockMode::WallClock) {
    executor_ = std::make_unique<core::RealtimeExecutor>(configurator_.clock(), configurator_.executorOptions());
    configurator_.watchHandovers(executor_.get());
  }
}

void Session::attachObserver() {
  for (const StudioSpec::Input& input : spec_.studio.inputs) {
    ActionSpec call;
    call.kind = ActionSpec::Kind::Call;
    call.component = input.call.substr(0, input.call.find('.'));
    call.member = memberOf(input.call);
    call.text = "call " + input.call + " (run.studio.inputs." + input.name + ")";
    call.lua_ref = input.lua_ref;
    call.where = input.where;
    checkAction(call, refs_, charts_, lua_.get());
    inputs_.push_back(std::move(call));
  }
  std::vector<statechart::ChartDescription> descriptions;
  for (Chart& c : charts_) {
    view_states_.push_back(&c.state);
    const statechart::Chart* loaded = c.supervisor->chart();
    descriptions.push_back(loaded != nullptr ? statechart::describe(*loaded) : statechart::ChartDescription{});
  }
  // The scenario: the option's, else the one the entry file chose (its global `scenario`).
  std::filesystem::path scenario = options_.scenario;
  lua_State* L = lua_.get();
  lua_getglobal(L, "scenario");
  if (scenario.empty() && lua_type(L, -1) == LUA_TSTRING) scenario = lua_tostring(L, -1);
  lua_pop(L, 1);
  options_.observer->attach({spec_, refs_, entry_, scenario, options_.report_folder, result_.clearance.threshold,
                             std::move(descriptions), scopes_, &configurator_});
}

void Session::attachCharts() {
  for (const ChartSpec& c : spec_.charts) {
    Chart chart;
    chart.spec = &c;
    const std::string use = "run.charts '" + c.name + "'";
    // On the wall clock the run observes every step of wall time, and a chart may pass through
    // a state between two observations: every state it enters waits in a buffer, taken in turn.
    chart.state_tap = std::make_unique<Tap<core::TaskState>>(
        refs_, c.supervisor + ".taskState", c.where.text(), use, "a Supervisor's taskState (TaskState)",
        options_.realtime ? core::ConnPolicy::buffer(256) : core::ConnPolicy::data());
    chart.supervisor = dynamic_cast<const components::Supervisor*>(refs_.find(c.supervisor));
    if (chart.supervisor == nullptr)
      throw std::runtime_error(c.where.text() + ": " + use + ": component '" + c.supervisor + "' is not a Supervisor");
    if (!options_.realtime) chart.state = chart.supervisor->activeState();
    chart.lane = c.name + " chart";
    charts_.push_back(std::move(chart));
  }
  // A component in Exception or FatalError is a failure the charts react to (noteComponentError):
  // the runner writes e_component_error into each chart's inputEvents, when one has a safe stop.
  if (std::none_of(spec_.charts.begin(), spec_.charts.end(), [](const ChartSpec& c) { return !c.safe_stop.empty(); }))
    return;
  component_error_events_ = std::make_unique<core::OutputPort<core::Event>>(
      "cobra_run_component_errors", "a component in Exception or FatalError (source: the component)", "");
  for (const ChartSpec& c : spec_.charts)
    if (core::PortBase* input = refs_.find(c.supervisor)->findPort("inputEvents"))
      core::connectPorts(*component_error_events_, *input, core::ConnPolicy::buffer(16));
}

void Session::armActions() {
  for (const ActionSpec& a : spec_.actions) armed_.push_back({a, false});
  std::filesystem::path faults = options_.faults_file;
  if (faults.empty() && !options_.scenario.empty() && std::filesystem::exists(options_.scenario / "faults.lua"))
    faults = options_.scenario / "faults.lua";
  if (!faults.empty()) {
    if (!std::filesystem::is_regular_file(faults))
      throw std::runtime_error("--faults " + faults.string() + ": no such file");
    for (ActionSpec& a : readFaults(lua_.get(), faults.string())) {
      const std::string host = remote_host_ ? remoteHostOfAction(a, remote_entries_, remote_host_) : "";
      if (host.empty()) armed_.push_back({std::move(a), true});
      else result_.log.push_back("fault " + a.where.text() + " played on host " + host);
    }
  }
  for (const Armed& a : armed_) checkAction(a.spec, refs_, charts_, lua_.get());
  lua_.run(std::string("cobra_run_play = (function() ") + kPlayer + " end)()", "=cobra run");
}

void Session::attachEventLog() {
  for (const core::Component* c : refs_.components())
    for (const char* port : {"events", "outputEvents"}) {
      auto* out = dynamic_cast<core::OutputPortBase*>(c->findPort(port));
      if (out == nullptr) continue;
      auto reader = out->makeReader(c->name() + "_" + port, "cobra run event log");
      auto* events = dynamic_cast<core::InputPort<core::Event>*>(reader.get());
      if (events != nullptr) reader->setNewDataFlag(&new_events_);
      out->connectTo(*reader, core::ConnPolicy::buffer(256));
      event_taps_.push_back({c->name(), std::move(reader), events});
    }
}

RunResult Session::run() {
  const auto start = std::chrono::steady_clock::now();
  const auto step = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(spec_.step));
  const double t0 = options_.realtime ? 0.0 : std::chrono::duration<double>(configurator_.clock().now()).count();
  if (executor_) runOnTheWallClock(step);
  else do {
    if (options_.realtime) {
      std::this_thread::sleep_for(step);
      t_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } else {
      configurator_.clock().advance(step);
      t_ = std::chrono::duration<double>(configurator_.clock().now()).count();
      dt_ = spec_.step;
      // Paced: simulated time is held back to `pace` simulated s per wall s (a viewer watches).
      if (options_.pace > 0.0)
        std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>((t_ - t0) / options_.pace)));
    }
    advance();
  } while (!ended());
  result_.duration = t_;
  // A lasting fault (every) was logged at its first play: how often it played in all.
  for (const Armed& a : armed_)
    if (a.spec.every > 0.0 && a.fired > 0)
      result_.log.push_back(std::string(a.fault ? "fault " : "action ") + a.spec.where.text() + " played " +
                            std::to_string(a.fired) + " times");
  noteExecutorFigures();
  for (const Chart& c : charts_) {
    result_.states_entered[c.spec->name] = timeline_.statesEntered(c.spec->name + " chart");
    result_.final_states.emplace_back(c.spec->name, c.state);
  }
  for (Observer* o : observers_) o->finish(result_);
  say(std::string("run ended: ") + toString(result_.outcome) + (result_.reason.empty() ? "" : ": " + result_.reason));
  std::vector<std::string> files;
  if (options_.observer != nullptr) files = options_.observer->finished(result_);
  if (!options_.report_folder.empty()) writeReport(files);
  return std::move(result_);
}

void Session::advance() {
  ++steps_;
  observeCharts();
  readEvents();
  observeSwitches();
  playActions();
  const bool records = steps_ % record_every_ == 0;
  stepObservers(true, records);
  if (records) recording_.sample(t_);
  if (options_.observer != nullptr) {
    std::size_t input = 0;
    while (options_.observer->nextInput(input) && input < inputs_.size()) {
      say("  input " + spec_.studio.inputs[input].name + ": " + inputs_[input].text);
      result_.log.push_back("input " + spec_.studio.inputs[input].name);
      play(inputs_[input]);
    }
    showToObserver();
  }
}

void Session::showToObserver() {
  options_.observer->step({t_, view_states_, shown_deployment_, scope_configuration_, shown_configuration_,
                           result_.clearance.last});
}

bool Session::observeCharts() {
  bool any = false;
  for (Chart& c : charts_) {
    if (options_.realtime) {
      // One state change per chart and call (the oldest not seen): advance() and catchUpStates()
      // take them in turn, so a state held for less than a step is still entered and left.
      core::TaskState task_state;
      c.previous = c.state;
      if (c.state_tap->readNew(task_state)) c.state.assign(task_state.path.view()), any = true;
      c.changed = steps_ == 1 || c.state != c.previous;
      continue;
    }
    // Lockstep: the chart's active leaf is one of its own strings, so the same pointer is the
    // same state; the strings are copied only when it changed (and once more the step after, to
    // make `previous` equal to it). What depends on the state alone (its folded form, the
    // timeline, the clearance's pauses) is worked out again only when `changed`: most steps leave
    // every chart where it was.
    const std::string_view leaf = c.supervisor->activeState();
    if (steps_ == 1 || leaf.data() != c.leaf || leaf.size() != c.state.size()) {
      c.previous = c.state;
      c.state.assign(leaf);
      c.leaf = leaf.data();
      c.changed = true;
    } else {
      if (c.changed) c.previous = c.state;
      c.changed = false;
    }
  }
  return any;
}

void Session::readEvents() {
  // Events are copied and formatted only when new (read copies the last sample every step, and
  // readText formats it too). One sample for all taps: making one zeroes 150 bytes.
  core::Event event_sample;
  const bool new_events = new_events_.exchange(false, std::memory_order_acquire);
  const auto take = [&](const std::string& source, const std::string& text) {
    Chart& chart = chartForSource(source);
    result_.events.push_back({t_, source, text, chart.state});
    const std::string event = text.substr(0, text.find(' '));
    result_.log.push_back(source + ": " + event);
    if (options_.observer != nullptr) options_.observer->event(t_, source, event);
    if (isFailure(event)) chart.last_failure = source + ": " + event + " at" + seconds(t_);
    chart.stall.heard(event, source, t_);
    for (Armed& a : armed_)
      if (a.due < 0.0 && (a.spec.repeat || a.fired == 0) && a.spec.on.kind == Trigger::Kind::Event &&
          a.spec.on.event == event && (a.spec.on.source.empty() || a.spec.on.source == source))
        a.due = t_ + a.spec.after;
  };
  // On the wall clock one observation may take events of several components at once (the
  // observer runs beside the executor, and late when the machine is busy): they are taken in the
  // order of their stamps, not of the taps, so that an answer never comes before what asked for
  // it. A tap without stamps (a text event port) keeps its place after the event before it.
  // Lockstep observes every instant, in the clock's order: taps in order, as before.
  struct Taken {
    std::int64_t stamp;
    const std::string* source;
    std::string text;
  };
  std::vector<Taken> taken;
  for (auto& [source, reader, typed] : event_taps_) {
    if (typed != nullptr && !new_events) continue;
    std::string text;
    std::int64_t stamp = taken.empty() ? std::numeric_limits<std::int64_t>::min() : taken.back().stamp;
    const auto next = [&] {
      if (typed == nullptr) return reader->readText(text) == core::FlowStatus::NewData;
      if (typed->readNew(event_sample) != core::FlowStatus::NewData) return false;
      text = core::DataTypeTraits<core::Event>::print(event_sample);
      stamp = event_sample.stamp.count();
      return true;
    };
    while (next()) {
      if (options_.realtime) taken.push_back({stamp, &source, std::move(text)});
      else take(source, text);
    }
  }
  std::stable_sort(taken.begin(), taken.end(), [](const Taken& a, const Taken& b) { return a.stamp < b.stamp; });
  for (const Taken& t : taken) take(*t.source, t.text);
  for (Chart& c : charts_) {
    if (!c.changed) continue;  // the timeline keeps an unchanged state's interval open
    c.stall.entered(t_);
    const std::string folded = foldState(c.state, spec_.fold);
    timeline_.observe(t_, c.lane, folded.empty() ? "(none)" : folded);
    if (folded == c.shown) continue;
    c.shown = folded;
    say(c.spec->name + " > " + folded);
    result_.log.push_back(c.spec->name + " > " + folded);
    if (options_.observer != nullptr) options_.observer->event(t_, c.spec->name, folded);
  }
}

void Session::observeSwitches() {
  const std::uint64_t switches = configurator_.switchCount();  // read first: a switch after it shows next step
  if (switches == switches_seen_) return;
  switches_seen_ = switches;
  bool switched = false;
  for (std::size_t s = 0; s < scopes_.size(); ++s) {
    const std::string& now = configurator_.currentDeployment(scopes_[s]);
    if (now == shown_deployment_[s]) continue;
    shown_deployment_[s] = now;
    switched = true;
    const std::string lane = (scopes_[s].empty() ? std::string() : scopes_[s] + " ") + "deployment";
    timeline_.observe(t_, lane, now.empty() ? "(none)" : now);
    result_.switches.push_back(seconds(t_) + " " + lane + " " + now);
    result_.log.push_back(lane + " > " + now);
    say("  " + lane + " -> " + now);
  }
  for (auto& [supervisor, seen] : switchers_) {
    if (supervisor->lastConfiguration() == seen) continue;
    seen.assign(supervisor->lastConfiguration());
    assignConfiguration(seen);
  }
  if (configurator_.currentConfiguration() != shown_configuration_) {
    shown_configuration_ = configurator_.currentConfiguration();
    assignConfiguration(shown_configuration_);
    result_.switches.push_back(seconds(t_) + " configuration " + shown_configuration_);
    result_.log.push_back("configuration > " + shown_configuration_);
    say("  configuration -> " + shown_configuration_);
  }
  // One timeline row per scope: the configuration in force over that scope's components.
  for (std::size_t s = 0; s < scopes_.size(); ++s) {
    if (scope_configuration_[s] == timeline_configuration_[s]) continue;
    timeline_configuration_[s] = scope_configuration_[s];
    timeline_.observe(t_, (scopes_[s].empty() ? std::string() : scopes_[s] + " ") + "configuration",
                      scope_configuration_[s].empty() ? "(none)" : scope_configuration_[s]);
  }
  if (switched) {  // a deployment may bring its own components
    components_ = refs_.components();
    listenToComponents();
  }
}

void Session::assignConfiguration(const std::string& name) {
  const deploy::DeploymentSet& set = configurator_.deploymentSet();
  const deploy::ConfigurationSpec* configuration = set.findConfiguration(name);
  bool any = false;
  for (std::size_t s = 0; s < scopes_.size() && configuration != nullptr; ++s) {
    const deploy::DeploymentSpec* deployment = set.findDeployment(shown_deployment_[s]);
    if (deployment == nullptr) continue;
    const bool sets = std::any_of(configuration->values.begin(), configuration->values.end(), [&](const auto& value) {
      return std::any_of(deployment->components.begin(), deployment->components.end(),
                         [&](const deploy::NameEntry& c) { return c.name == value.component; });
    });
    if (sets) scope_configuration_[s] = name, any = true;
  }
  if (!any) std::fill(scope_configuration_.begin(), scope_configuration_.end(), name);
}

void Session::playActions() {
  for (Armed& a : armed_) {
    if (a.due < 0.0 && (a.spec.repeat || a.fired == 0)) {
      if (a.spec.on.kind == Trigger::Kind::Time && a.fired == 0 && t_ + 1e-9 >= a.spec.on.time) a.due = t_ + a.spec.after;
      if (a.spec.on.kind == Trigger::Kind::State) {
        const Chart& c = *chartOf(a.spec.on.chart);
        if (startsWith(c.state, a.spec.on.state) && !startsWith(c.previous, a.spec.on.state)) a.due = t_ + a.spec.after;
      }
    }
    if (a.due < 0.0 || t_ + 1e-9 < a.due) continue;
    // Played again every `every` s (a fault that lasts); once per trigger otherwise.
    a.due = a.spec.every > 0.0 ? a.due + a.spec.every : -1.0;
    if (a.spec.chance < 1.0 && std::uniform_real_distribution<double>(0.0, 1.0)(a.random) >= a.spec.chance) continue;
    if (++a.fired > 1 && a.spec.every > 0.0) {
      play(a.spec);  // logged at its first play only
      continue;
    }
    const std::string label = std::string(a.fault ? "fault " : "action ") + a.spec.where.text();
    say("  " + label + " (on " + a.spec.on.text() + "): " + a.spec.text);
    result_.log.push_back(label);
    play(a.spec);
  }
}

void Session::runOnTheWallClock(std::chrono::nanoseconds step) {
  // The executor steps the deployment on its real-time thread; this thread observes through the
  // run's taps (ports) every `step` of wall time and plays actions between two ticks. It is
  // stopped on every way out, before anything the run owns is torn down.
  struct Stop {
    core::RealtimeExecutor& executor;
    ~Stop() { executor.stop(); }
  } stop{*executor_};
  executor_->start();
  // The run's observation (tracking, clearance, recording, actions) is its measuring instrument:
  // on a loaded machine a SCHED_OTHER thread was seen to oversleep by 0.4 s. It runs SCHED_FIFO at
  // the lowest priority, under the executor's, when the executor got SCHED_FIFO (and as it was
  // otherwise); its old scheduling comes back when the run ends.
  struct Observing {
    int policy = SCHED_OTHER;
    sched_param old{};
    bool raised = false;
    explicit Observing(bool raise) {
      if (!raise || pthread_getschedparam(pthread_self(), &policy, &old) != 0) return;
      sched_param observer{};
      observer.sched_priority = 1;
      raised = pthread_setschedparam(pthread_self(), SCHED_FIFO, &observer) == 0;
    }
    ~Observing() {
      if (raised) pthread_setschedparam(pthread_self(), policy, &old);
    }
  } observing(executor_->effectiveScheduler() == core::Scheduler::Fifo);
  // Every step of wall time, never catching up: a late observation samples the state then (the
  // executor does not wait for it), and a thread at a SCHED_FIFO priority must sleep between two,
  // or the threads of ordinary priority (own-pace planners, the DDS link's) would starve.
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(step);
  auto next = std::chrono::steady_clock::now();
  do {
    next += period;
    const auto now = std::chrono::steady_clock::now();
    if (next <= now) next = now + period / 4;  // late: a short rest, then observe
    std::this_thread::sleep_until(next);
    const double before = t_;
    t_ = std::chrono::duration<double>(configurator_.clock().now()).count();
    dt_ = steps_ == 0 ? spec_.step : t_ - before;
    advance();
    // States entered since this observation's first are shown too (the last ones of a run would
    // otherwise never reach the studio: the run ends with them).
    if (catchUpStates() && options_.observer != nullptr) showToObserver();
  } while (!ended());
}

bool Session::catchUpStates() {
  // The states a chart entered since the observation took its first: what depends on a chart's
  // state (the log and timeline, summaries sampled on leaving a state, actions on entering one)
  // sees each of them, at this observation's time.
  // Afterwards `previous` is again the state one observation ago, as ended() expects.
  catch_up_previous_.resize(charts_.size());
  for (std::size_t i = 0; i < charts_.size(); ++i) catch_up_previous_[i] = charts_[i].previous;
  bool any = false;
  for (int round = 0; round < 256 && observeCharts(); ++round) {
    any = true;
    readEvents();
    playActions();
    stepObservers(false, false);
  }
  for (std::size_t i = 0; i < charts_.size(); ++i) {
    charts_[i].previous = catch_up_previous_[i];
    charts_[i].changed = charts_[i].state != charts_[i].previous;
  }
  return any;
}

void Session::play(const ActionSpec& action) {
  if (executor_) executor_->runBetweenTicks([&] { playNow(action); });
  else playNow(action);
}

void Session::playNow(const ActionSpec& action) {
  if (action.kind == ActionSpec::Kind::Throw) {
    core::injectUpdateException(*refs_.find(action.component), "injected fault (" + action.where.text() + ")");
    return;
  }
  lua_State* L = lua_.get();
  lua_getglobal(L, "cobra_run_play");
  lua_rawgeti(L, LUA_REGISTRYINDEX, action.lua_ref);
  lua_pushstring(L, action.where.text().c_str());
  if (lua_pcall(L, 2, 0, 0) != LUA_OK) {
    std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(no message)";
    lua_pop(L, 1);
    // The bindings put their Lua caller's place first: the player's, not the user's file.
    if (startsWith(message, "cobra run:")) message.erase(0, message.find(": ") + 2);
    char when[32];
    std::snprintf(when, sizeof when, "%.3f s", t_);
    throw std::runtime_error(action.where.text() + ": " + action.text + " failed at " + when + ": " + message);
  }
}

void Session::dropOtherHostsEntries() {
  if (configurator_.placement() == nullptr) return;
  remote_host_ = [this](const std::string& component) {
    return configurator_.isRemote(component) ? configurator_.placement()->hostOf(component, {}) : std::string();
  };
  remote_entries_ = dropRemoteEntries(spec_, remote_host_);
  for (const auto& [host, entries] : remote_entries_.by_host) {
    std::string list;
    for (const std::string& e : entries) list += (list.empty() ? "" : ", ") + e;
    say("observed on host " + host + ": " + list);
    result_.log.push_back("observed on host " + host + ": " + list);
  }
}

Chart* Session::chartOf(const std::string& name) {
  for (Chart& c : charts_)
    if (c.spec->name == name) return &c;
  return nullptr;
}

Chart& Session::chartForSource(const std::string& source) {
  for (Chart& c : charts_)
    for (const std::string& prefix : c.spec->sources)
      if (startsWith(source, prefix)) return c;
  return charts_.front();  // the first chart receives the events of the sources no chart lists
}

std::string Session::statesText() const {
  std::string text;
  for (const Chart& c : charts_) text += (text.empty() ? "" : ", ") + c.spec->name + " " + c.state;
  return text;
}

void Session::say(const std::string& what) const {
  if (options_.progress) options_.progress(seconds(t_) + "  " + what);
}

}  // namespace cobra::run
