// How a run ends (Session's side, session.hpp): a chart in its safe stop, a component in error
// told to the charts, the peers of a run split over hosts, and decide(), which looks at all of
// them once per step.

#include "session.hpp"

#include <algorithm>
#include <cstdio>

#include "cobra/components/coordination/supervisor.hpp"

namespace cobra::run {
namespace {

/// The switch supervisors' answers to a refused switch (components/coordination/charts/
/// switch_supervisor.lua): always a failure, whatever the run table's `failures` lists.
constexpr std::pair<const char*, const char*> kSwitchFailures[] = {{"e_configure_failed_", "configuration"},
                                                                    {"e_deploy_failed_", "deployment"}};

}  // namespace

void Session::noteSafeStop(const Chart& c) {
  result_.log.push_back(c.spec->name + " safe stop");
  if (result_.outcome == Outcome::SafeStop) return;
  result_.outcome = Outcome::SafeStop;
  safe_stop_at_ = t_;
  result_.reason = c.spec->name + " chart stopped safely in " + foldState(c.previous, spec_.fold) + ": " +
                   (c.last_failure.empty() ? "(no failure event seen)" : c.last_failure) +
                   (spec_.safe_stop_reason.empty() ? "" : ", " + spec_.safe_stop_reason);
  // "Source: event at t s": the source's declared operation says why (e.g. the planner's reason).
  const auto colon = c.last_failure.find(": ");
  if (colon != std::string::npos) {
    const std::string source = c.last_failure.substr(0, colon);
    const std::string event = c.last_failure.substr(colon + 2, c.last_failure.find(" at") - colon - 2);
    // The run table's `explain` operation for the event, else the source's own `lastFailure()`
    // (the simulated robots': the refused pose and why), when it has one.
    const auto why = spec_.explain.find(event);
    const std::string operation = why == spec_.explain.end() ? "lastFailure" : why->second;
    // A component error: its own text (the component's lastError) says why (below).
    core::Component* owner = event == kComponentErrorEvent ? nullptr : ownerOf(refs_, source + "." + operation, true);
    if (owner != nullptr) {
      try {
        result_.reason += "; " + source + "." + operation + "(): " + owner->call<std::string>(operation);
      } catch (const std::exception& e) {  // not a std::string() operation: the reason stays as it is
        result_.log.push_back("cannot quote " + source + "." + operation + "(): " + e.what());
      }
    }
  }
  // A refused switch: the configurator's line says why (file:line, property, what was expected).
  if (colon != std::string::npos) {
    const std::string event = c.last_failure.substr(colon + 2, c.last_failure.find(" at") - colon - 2);
    for (const auto& [prefix, kind] : kSwitchFailures)
      if (startsWith(event, prefix)) {
        const std::string why = configurator_.lastWarningWith(" asked for " + std::string(kind) + " '" +
                                                              event.substr(std::string_view(prefix).size()) + "': ");
        if (!why.empty()) result_.reason += "; " + why;
      }
  }
  // A component in error before the safe stop is named whichever failure the chart heard last.
  if (!component_error_.empty()) result_.reason += "; " + component_error_;
  say("SAFE STOP: " + result_.reason);
}

bool Session::noteComponentError(const core::Component& component, const std::string& text) {
  result_.log.push_back(text);
  if (component_error_events_ == nullptr || result_.outcome == Outcome::SafeStop) {
    // No chart can stop safely (or one already has): the error ends the run as it is.
    if (result_.outcome == Outcome::SafeStop) return false;
    result_.outcome = Outcome::ComponentError;
    result_.reason = text;
    return true;
  }
  if (component_error_at_ < 0.0) component_error_at_ = t_, component_error_ = text;
  say("COMPONENT ERROR: " + text + "; the charts are told (" + kComponentErrorEvent + ")");
  // As an event of the component: the charts' failure transitions take it, the log and the
  // observers see it, and a safe stop names it (noteSafeStop quotes `text`).
  core::Event event;
  event.name.assign(kComponentErrorEvent);
  event.source.assign(component.name());
  event.stamp = std::chrono::duration_cast<std::chrono::nanoseconds>(configurator_.clock().now());
  component_error_events_->write(event);
  for (Chart& c : charts_) {
    c.last_failure = component.name() + ": " + kComponentErrorEvent + " at" + seconds(t_);
    c.stall.heard(kComponentErrorEvent, component.name(), t_);
  }
  Chart& chart = chartForSource(component.name());
  result_.events.push_back({t_, component.name(), kComponentErrorEvent, chart.state});
  result_.log.push_back(component.name() + ": " + kComponentErrorEvent);
  if (options_.observer != nullptr) options_.observer->event(t_, component.name(), kComponentErrorEvent);
  return false;
}

bool Session::isFailure(const std::string& event) const {
  if (event == kComponentErrorEvent) return true;
  for (const auto& [prefix, kind] : kSwitchFailures)
    if (startsWith(event, prefix)) return true;
  return std::find(spec_.failures.begin(), spec_.failures.end(), event) != spec_.failures.end();
}

bool Session::ended() {
  if (decided_at_ >= 0.0) {
    const bool interrupted = options_.interrupt != nullptr && options_.interrupt->load(std::memory_order_relaxed);
    return interrupted || t_ - decided_at_ >= options_.watch_after_end - 1e-9;
  }
  if (!decide()) return false;
  if (options_.watch_after_end <= 0.0 || result_.outcome == Outcome::Interrupted) return true;
  // The outcome stands; the run steps on so that the robots are watched (and recorded) after it.
  decided_at_ = t_;
  result_.log.push_back("run decided: " + std::string(toString(result_.outcome)));
  say("run decided: " + std::string(toString(result_.outcome)) + "; watching for" + seconds(options_.watch_after_end));
  return false;
}

bool Session::decide() {
  if (executor_ && executor_->safeStopAsked() && result_.outcome != Outcome::SafeStop) {
    result_.outcome = Outcome::SafeStop;
    safe_stop_at_ = t_;
    result_.reason = "executor: " + std::to_string(executor_->options().policy.safe_stop_after) +
                     " consecutive deadline misses of its " + core::formatDuration(executor_->options().period) +
                     " period (setExecutor's safe_stop_after)";
    say("SAFE STOP: " + result_.reason);
  }
  // Ctrl-C first: a script it cut short is in Exception because of it.
  if (options_.interrupt != nullptr && options_.interrupt->load(std::memory_order_relaxed)) {
    result_.outcome = Outcome::Interrupted;
    char at[48];
    std::snprintf(at, sizeof at, "interrupted at %.3f s", t_);
    result_.reason = std::string(at) + "; charts: " + statesText();
    return true;
  }
  for (const Chart& c : charts_)
    if (!c.spec->safe_stop.empty() && c.state == c.spec->safe_stop && c.previous != c.spec->safe_stop) noteSafeStop(c);
  // The components' states are looked at only after one was announced to enter Exception or
  // FatalError (and once at the start): no polling of every component every step.
  // Each component found in error is noted once (errors_noted_): the count read first, a change
  // after the look shows at the next step.
  if (const std::uint64_t errors = component_errors_.count(); errors != component_errors_seen_) {
    component_errors_seen_ = errors;
    for (const core::Component* c : components_) {
      const core::State s = c->state();
      if (s != core::State::Exception && s != core::State::FatalError) continue;
      if (std::find(errors_noted_.begin(), errors_noted_.end(), c) != errors_noted_.end()) continue;
      errors_noted_.push_back(c);
      if (noteComponentError(*c, "component '" + c->name() + "' is in " + std::string(core::toString(s)) + ": " +
                                     c->lastError()))
        return true;
    }
  }
  // Told to the charts, the component error stands unless one of them reached its safe stop in
  // time: a chart that cannot react must not hide it.
  if (component_error_at_ >= 0.0 && result_.outcome != Outcome::SafeStop &&
      t_ - component_error_at_ >= spec_.safe_stop_linger - 1e-9) {
    char within[128];
    std::snprintf(within, sizeof within, "; no chart reached its safe stop within %.3f s of %s (told at %.3f s): ",
                  spec_.safe_stop_linger, kComponentErrorEvent, component_error_at_);
    result_.outcome = Outcome::ComponentError;
    result_.reason = component_error_ + within + statesText();
    return true;
  }
  notePeerLoss();
  if (steps_ % 100 == 1) notePeerJoins();
  if (std::all_of(charts_.begin(), charts_.end(), [](const Chart& c) { return c.state == c.spec->done; }) &&
      !peersHoldTheRun()) {
    result_.outcome = peer_lost_at_ >= 0.0 ? Outcome::PeerLost : Outcome::Completed;
    result_.reason = peer_lost_at_ >= 0.0 ? lost_peers_ + "; this host's charts had completed" : "";
    return true;
  }
  if (result_.outcome == Outcome::SafeStop) {
    const bool stopped = std::all_of(charts_.begin(), charts_.end(), [](const Chart& c) {
      return c.state == c.spec->done || c.state == c.spec->safe_stop;
    });
    // Split over hosts: the peers are told, and waited for (as long as the other charts are).
    // After a peer's loss the robots are watched holding still for that long too (the record
    // shows them stopped).
    const bool peers_settled =
        peer_lost_at_ >= 0.0 ? t_ - peer_lost_at_ >= spec_.safe_stop_linger : !peersHoldTheRun();
    if ((stopped && peers_settled) || t_ - safe_stop_at_ >= spec_.safe_stop_linger) {
      if (peer_lost_at_ >= 0.0) result_.outcome = Outcome::PeerLost, result_.reason = lost_peers_ + "; " + result_.reason;
      return true;
    }
  }
  if (peer_lost_at_ >= 0.0 && result_.outcome != Outcome::SafeStop && t_ - peer_lost_at_ >= spec_.safe_stop_linger) {
    result_.outcome = Outcome::PeerLost;
    result_.reason = lost_peers_ + "; this host's charts did not reach a safe stop within " +
                     seconds(spec_.safe_stop_linger) + ": " + statesText();
    return true;
  }
  for (Chart& c : charts_)
    if (c.stall.due(t_, spec_.stall_notice)) {
      const std::string text = c.stall.text(c.spec->name, c.state, c.supervisor->chart());
      result_.log.push_back(text);
      say(text);
    }
  if (t_ >= options_.time_limit - 1e-9) {
    char limit[64];
    std::snprintf(limit, sizeof limit, "time limit %.3f s reached", options_.time_limit);
    const auto fault = std::find_if(armed_.begin(), armed_.end(), [](const Armed& a) { return a.fault && a.fired > 0; });
    if (fault != armed_.end()) {
      result_.outcome = Outcome::UnhandledFault;
      result_.reason = std::string(limit) + " after fault " + fault->spec.where.text() + " (" + fault->spec.text +
                       "): the task did not recover; charts: " + statesText();
    } else {
      result_.outcome = Outcome::TimeLimit;
      result_.reason = std::string(limit) + "; charts: " + statesText();
      for (const Chart& c : charts_)
        if (c.state != c.spec->done) result_.reason += "; " + c.stall.text(c.spec->name, c.state, c.supervisor->chart());
    }
    return true;
  }
  if (t_ >= next_progress_) {
    next_progress_ += options_.progress_every;
    say("running; " + statesText());
  }
  return false;
}

bool Session::peersHoldTheRun() {
  core::ClockSync* sync = configurator_.clockSync();
  if (sync == nullptr) return false;
  if (options_.realtime) {
    // On the wall clock nothing meets the peers: each host's run ends with its own charts, and
    // its link's farewell tells them it completed (a farewell without it is a lost peer).
    sync->setDone(true);
    return false;
  }
  if (!told_done_) {
    sync->setDone(true);
    told_done_ = true;
    say("this host's charts ended; waiting for its peers");
    // The peers hear it at the next meeting (peersDone is false until then), or a peer waiting
    // for it would find this host gone instead (and end with a lost peer).
    return true;
  }
  return !sync->peersDone();
}

void Session::notePeerLoss() {
  const core::ClockSync* sync = configurator_.clockSync();
  if (sync == nullptr || peer_lost_at_ >= 0.0) return;
  const std::vector<std::string> lost = sync->lostPeers();
  if (lost.empty()) return;
  peer_lost_at_ = t_;
  std::string names;
  for (const std::string& n : lost) names += (names.empty() ? "'" : ", '") + n + "'";
  lost_peers_ = "peer " + names + " lost at" + seconds(t_);
  result_.log.push_back("peer lost: " + names);
  say("PEER LOST: " + lost_peers_);
}

}  // namespace cobra::run
