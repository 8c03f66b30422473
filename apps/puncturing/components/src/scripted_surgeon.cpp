#include "cobra/components/puncturing/scripted_surgeon.hpp"

#include <algorithm>
#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {
namespace {

using Trigger = puncturing::SurgeonAction::Trigger;

std::chrono::nanoseconds seconds(double s) {
  return std::chrono::nanoseconds(static_cast<long long>(s * 1e9 + (s >= 0 ? 0.5 : -0.5)));
}

}  // namespace

ScriptedSurgeon::ScriptedSurgeon(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "the surgeon's console in simulation: plays a surgeon script against the puncturing task charts, "
                "and says surgeon events on request") {
  addProperty(script_file_);
  addProperty(max_pending_.range(1, 100000));
  addProperty(dropped_.readOnly());
  addPort(needle_state_);
  addPort(us_state_);
  std::string allowed;
  for (const std::string& e : puncturing::surgeonEvents()) allowed += (allowed.empty() ? "" : ", ") + e;
  addOperation("say", &ScriptedSurgeon::say, this, "emits a surgeon event now, one of: " + allowed)
      .arg("event", "", "the event name");
}

bool ScriptedSurgeon::configureHook() {
  if (script_file_().empty()) return refuse("property script_file is empty; give the path of a surgeon script");
  try {
    script_ = puncturing::parseSurgeonScript(puncturing::readText(script_file_()), script_file_());
  } catch (const std::invalid_argument& e) {
    script_ = {};
    return refuse(e.what());
  }
  used_.assign(script_.actions.size(), 0);
  fired_now_.assign(script_.actions.size(), 0);
  pending_.clear();
  pending_.reserve(static_cast<std::size_t>(max_pending_()));
  dropped_.setFromOwner(0);
  return true;
}

bool ScriptedSurgeon::startHook() {
  if (activity().period() <= std::chrono::nanoseconds::zero())
    return refuse("needs a periodic activity: the script's times and delays are checked at every period");
  std::fill(used_.begin(), used_.end(), 0);
  pending_.clear();
  last_[0] = {};
  last_[1] = {};
  start_ = now();
  return true;
}

void ScriptedSurgeon::changed(std::string_view chart, std::string_view previous, std::string_view path) noexcept {
  std::fill(fired_now_.begin(), fired_now_.end(), 0);
  for (std::size_t i = 0; i < script_.actions.size(); ++i) {
    const puncturing::SurgeonAction& a = script_.actions[i];
    if (a.trigger != Trigger::OnState || a.chart != chart) continue;
    if (!puncturing::pathContains(path, a.state) || puncturing::pathContains(previous, a.state)) continue;
    if (a.times != 0 && used_[i] >= a.times) continue;
    // One line per state entered: the first line for this state not used up.
    bool taken = false;
    for (std::size_t k = 0; k < i && !taken; ++k) {
      taken = fired_now_[k] && script_.actions[k].chart == a.chart && script_.actions[k].state == a.state;
    }
    if (taken) continue;
    ++used_[i];
    fired_now_[i] = 1;
    if (pending_.size() == pending_.capacity()) {
      dropped_.setFromOwner(dropped_() + 1);
      continue;
    }
    pending_.push_back({now() + seconds(a.after), i});
  }
}

void ScriptedSurgeon::updateHook() {
  core::InputPort<core::TaskState>* ports[2] = {&needle_state_, &us_state_};
  const std::string_view charts[2] = {"needle", "us"};
  for (std::size_t c = 0; c < 2; ++c) {
    while (ports[c]->read(sample_) == core::FlowStatus::NewData) {
      if (sample_ == last_[c]) continue;
      changed(charts[c], last_[c].path.view(), sample_.path.view());
      last_[c] = sample_;
    }
  }
  const std::chrono::nanoseconds t = now();
  for (std::size_t i = 0; i < script_.actions.size(); ++i) {
    const puncturing::SurgeonAction& a = script_.actions[i];
    if (a.trigger != Trigger::At || used_[i] != 0 || t < start_ + seconds(a.at)) continue;
    used_[i] = 1;
    emitEvent(a.event);
  }
  // Due triggered events, in the order they were scheduled (erase keeps the capacity).
  for (std::size_t k = 0; k < pending_.size();) {
    if (pending_[k].due <= t) {
      emitEvent(script_.actions[pending_[k].action].event);
      pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(k));
    } else {
      ++k;
    }
  }
}

void ScriptedSurgeon::say(const std::string& event) {
  const auto& allowed = puncturing::surgeonEvents();
  if (std::find(allowed.begin(), allowed.end(), event) == allowed.end()) {
    std::string list;
    for (const std::string& e : allowed) list += (list.empty() ? "" : ", ") + e;
    throw std::invalid_argument("'" + event + "' is not a surgeon event; say one of: " + list);
  }
  emitEvent(event);
}

}  // namespace cobra::components
