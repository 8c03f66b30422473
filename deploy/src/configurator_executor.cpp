// The wall clock's executor as the deployment files declare it (setExecutor, spec.hpp).
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>

#include "cobra/core/component.hpp"
#include "cobra/deploy/configurator.hpp"

namespace cobra::deploy {
namespace {

/// `Executor`: the real-time executor's voice in the deployment. It steps nothing; the run's
/// executor writes `e_deadline_missed` / `e_deadline_safe_stop` on its events port from the
/// executor's thread (Component::emitEvent is real-time safe).
class ExecutorMonitor final : public core::Component {
 public:
  ExecutorMonitor()
      : core::Component("Executor", core::Role::Bridge,
                        "The real-time executor of the wall clock: its events port carries e_deadline_missed (the "
                        "first of a run of missed periods, when setExecutor's on_deadline_miss is \"event\") and "
                        "e_deadline_safe_stop (safe_stop_after consecutive misses), and e_handover_stale_<component> "
                        "when what a component at its own pace hands over is older than its activity's max_age. "
                        "Silent on the lockstep clock.") {}
};

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%g s", s);
  return text;
}

}  // namespace

void Configurator::setExecutor(ExecutorSpec spec) {
  const std::lock_guard lock(mutex_);
  const std::string head = spec.where.text() + ": setExecutor: ";
  if (executor_.declared)
    throw core::Error(head + "the executor is set already (" + executor_.where.text() + "); set it once");
  if (!std::isfinite(spec.period) || spec.period < 0.0 || (spec.period > 0.0 && spec.period < 1e-6))
    throw core::Error(head + "period must be a number of seconds >= 1e-6 (0: the periods' greatest common divisor), got " +
                      std::to_string(spec.period));
  if (toScheduler(spec.scheduler, spec.where) == core::Scheduler::Fifo && (spec.priority < 1 || spec.priority > 99))
    throw core::Error(head + "priority " + std::to_string(spec.priority) + " is outside 1..99 for " + spec.scheduler);
  const int cpus = static_cast<int>(std::thread::hardware_concurrency());
  if (spec.cpu < -1 || (cpus > 0 && spec.cpu >= cpus))
    throw core::Error(head + "cpu " + std::to_string(spec.cpu) + " does not exist: this machine has CPUs 0.." +
                      std::to_string(cpus - 1) + " (-1: any)");
  if (spec.on_deadline_miss != "count" && spec.on_deadline_miss != "event")
    throw core::Error(head + "on_deadline_miss is \"count\" or \"event\", got \"" + spec.on_deadline_miss + "\"");
  if (spec.safe_stop_after < 0)
    throw core::Error(head + "safe_stop_after must be >= 0 (0: never), got " + std::to_string(spec.safe_stop_after));
  if (components_.find("Executor") != nullptr)
    throw core::Error(head + "a component is named 'Executor' already; the executor's component needs that name");
  spec.declared = true;
  core::Component& monitor = components_.add(std::make_unique<ExecutorMonitor>());
  types_["Executor"] = "Executor";
  (void)monitor.configure();
  (void)monitor.start();
  started_.push_back("Executor");
  executor_monitor_ = &monitor;
  executor_ = std::move(spec);
}

void Configurator::watchHandovers(core::RealtimeExecutor* executor) {
  const std::lock_guard lock(mutex_);
  handover_watcher_ = executor;
  if (executor == nullptr || options_.mode != ClockMode::WallClock) return;
  for (const auto& [name, activity] : activities_)
    if (activity.own_pace)
      executor->watchHandover(component(name, activity.where),
                             std::chrono::nanoseconds(std::llround(activity.handoverBound() * 1e9)));
}

core::ExecutorOptions Configurator::executorOptions() const {
  const std::lock_guard lock(mutex_);
  core::ExecutorOptions options;
  const auto ns = [](double s) { return std::chrono::nanoseconds(std::llround(s * 1e9)); };
  const std::string head = executor_.where.text() + ": setExecutor: ";
  std::int64_t tick = 0;
  for (const auto& [name, activity] : activities_)
    if (activity.period > 0.0 && !(activity.own_pace && options_.mode == ClockMode::WallClock))
      tick = std::gcd(tick, ns(activity.period).count());
  if (executor_.period > 0.0) {
    options.period = ns(executor_.period);
    for (const auto& [name, activity] : activities_) {
      if (activity.period <= 0.0 || (activity.own_pace && options_.mode == ClockMode::WallClock)) continue;
      if (ns(activity.period) % options.period != std::chrono::nanoseconds(0))
        throw core::Error(head + "period " + seconds(executor_.period) + " does not divide the period " +
                          seconds(activity.period) + " of '" + name + "' (its activity at " + activity.where.text() +
                          "); give a period that divides every periodic component's, or 0 for their greatest "
                          "common divisor");
    }
  } else {
    options.period = std::chrono::nanoseconds(tick > 0 ? tick : 1'000'000);
  }
  options.priority = executor_.priority;
  options.scheduler = toScheduler(executor_.scheduler, executor_.where);
  options.cpu = executor_.cpu;
  options.lock_memory = executor_.lock_memory;
  options.policy.emit_event = executor_.on_deadline_miss == "event";
  options.policy.safe_stop_after = executor_.safe_stop_after;
  if (executor_monitor_ != nullptr) {
    core::Component* monitor = executor_monitor_;
    options.on_event = [monitor](const char* event) { monitor->emitEvent(event); };
  }
  return options;
}

}  // namespace cobra::deploy
