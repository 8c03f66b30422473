// A Session's observers (observer.hpp) and its report: the sections of the run table attached by
// their registered observers and stepped every observation; the components' state changes heard
// (core::StateListener); the run folder written (events.csv, signals.csv, then every registered
// ReportWriter: tools/report's report.html).
#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "session.hpp"

namespace cobra::run {

core::Component* ownerOf(const core::ComponentRegistry& refs, const std::string& path, bool operation) {
  const auto dot = path.find('.');
  if (dot == std::string::npos) return nullptr;
  core::Component* owner = refs.find(path.substr(0, dot));
  if (owner == nullptr) return nullptr;
  const std::string member = path.substr(dot + 1);
  return (operation ? owner->findOperation(member) != nullptr : owner->findProperty(member) != nullptr) ? owner
                                                                                                       : nullptr;
}

std::string memberOf(const std::string& path) { return path.substr(path.find('.') + 1); }

Session::~Session() { configurator_.watchHandovers(nullptr); }

void Session::attachObservers() {
  for (const Chart& c : charts_) chart_states_.push_back(&c);
  context_ = std::make_unique<ObserverContext>(ObserverContext{
      spec_, refs_, configurator_, chart_states_, recording_, result_, options_.realtime,
      [this](const std::string& line) { say(line); }});
  for (const ObserverSection& section : spec_.observers) observers_.push_back(section.observer.get());
  for (Observer* o : observers_) o->attach(*context_);
  for (Observer* o : observers_) o->attached(*context_);
}

void Session::listenToComponents() {
  component_errors_.listenToAll();
  component_errors_seen_ = UINT64_MAX;  // look at every state once: one may have failed before
}

void Session::stepObservers(bool full, bool records) {
  const Moment now{t_, dt_, full, records};
  for (Observer* o : observers_) o->step(now);
}

void Session::writeReport(const std::vector<std::string>& observer_files) {
  RunReport run;
  run.title = spec_.title + (options_.scenario.empty() ? "" : ": " + options_.scenario.filename().string());
  run.summary = {{"application", entry_.string()},
                 {"result", std::string(toString(result_.outcome)) + (result_.reason.empty() ? "" : ": " + result_.reason)},
                 {"duration", seconds(result_.duration)},
                 {"deployment/configuration switches", std::to_string(result_.switches.size())}};
  if (!options_.scenario.empty()) run.summary.insert(run.summary.begin() + 1, {"scenario", options_.scenario.string()});
  for (const SummaryValue& v : result_.summary) run.summary.emplace_back(v.name, v.text);
  run.events = result_.events;
  run.timeline = timeline_.intervals(result_.duration);
  for (const Observer* o : observers_) o->report(run, recording_);
  dropEmpty(run.figures);
  for (auto& row : executorRows(result_.executor, 12)) run.summary.push_back(std::move(row));
  run.files.insert(run.files.begin(), "signals.csv");
  run.files.insert(run.files.end(), observer_files.begin(), observer_files.end());
  const std::filesystem::path& folder = options_.report_folder;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw std::runtime_error("cobra run: cannot create folder " + folder.string() + ": " + error.message());
  const auto write = [](const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cobra run: cannot write " + path.string());
  };
  write(folder / "events.csv", eventLogCsv(run.events));
  write(folder / "signals.csv", recording_.csv());
  for (const ReportWriter& writer : ObserverRegistry::reportWriters()) {
    const std::filesystem::path page = writer(folder, run);
    if (result_.report.empty()) result_.report = page;
  }
}

void Session::noteExecutorFigures() {
  if (!executor_) return;
  ExecutorFigures& f = result_.executor;
  const core::ExecutorOptions& o = executor_->options();
  f.ran = true;
  f.period = std::chrono::duration<double>(o.period).count();
  f.scheduler = o.scheduler == core::Scheduler::Fifo && executor_->effectiveScheduler() == core::Scheduler::Fifo
                    ? "SCHED_FIFO priority " + std::to_string(o.priority)
                    : std::string("SCHED_OTHER") + (o.scheduler == core::Scheduler::Fifo ? " (SCHED_FIFO refused)" : "");
  f.memory_locked = executor_->memoryLocked();
  f.ticks = executor_->ticks();
  f.deadline_misses = executor_->deadlineMisses();
  f.worst_consecutive_misses = executor_->worstConsecutiveMisses();
  f.slipped = std::chrono::duration<double>(executor_->slipped()).count();
  f.wake_latency = core::figuresOf(executor_->wakeLatency());
  f.tick_compute = core::figuresOf(executor_->tickCompute());
  f.between_steps = core::figuresOf(executor_->betweenSteps());
  f.work_between_ticks = core::figuresOf(executor_->workBetweenTicks());
  f.components = executor_->componentTimings();
  f.handovers = executor_->handoverFigures();
  f.warnings = executor_->warnings();
}

void Session::notePeerJoins() {
  // The link's e_peer_joined may come while this host is still loading, before the event log
  // listens to it: the run asks the link which peers it has heard from (operation joinedPeers).
  const auto* link = dynamic_cast<const core::Component*>(configurator_.clockSync());
  core::OperationBase* joined = link == nullptr ? nullptr : link->findOperation("joinedPeers");
  if (joined == nullptr) return;
  std::istringstream names(joined->invokeFromText({}));
  for (std::string name; std::getline(names, name, ',');) {
    if (std::find(joined_peers_.begin(), joined_peers_.end(), name) != joined_peers_.end()) continue;
    joined_peers_.push_back(name);
    result_.log.push_back("peer joined: '" + name + "'");
    say("peer '" + name + "' joined");
  }
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
