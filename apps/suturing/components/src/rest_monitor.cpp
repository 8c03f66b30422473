#include "cobra/components/suturing/rest_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace cobra::components {

RestMonitor::RestMonitor(std::string name)
    : Component(std::move(name), core::Role::Decision,
                "Whether the two tools are at rest (measured poses still within tolerances over a window), on request") {
  addProperty(tolerance_);
  addProperty(angle_tolerance_);
  addProperty(window_);
  addPort(right_);
  addPort(left_);
  addOperation("askAtRest", std::function<void()>([this] { ask_.ask(activity()); }),
               "answered by e_at_rest once both tools are at rest (at once when they are)");
}

bool RestMonitor::configureHook() {
  // Each must be finite and > 0 (a NaN fails the comparison).
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(tolerance_()))
    return refuse("property tolerance is " + std::to_string(tolerance_()) + " m; expected a finite value > 0 m");
  if (!positive(angle_tolerance_()))
    return refuse("property angle_tolerance is " + std::to_string(angle_tolerance_()) +
                  " rad; expected a finite value > 0 rad");
  if (!positive(window_()))
    return refuse("property window is " + std::to_string(window_()) + " s; expected a finite value > 0 s");
  return true;
}

bool RestMonitor::startHook() {
  ask_.clear();
  asked_ = false;
  right_tool_ = left_tool_ = Tool{};
  return true;
}

void RestMonitor::watch(core::InputPort<KDL::Frame>& port, Tool& tool) noexcept {
  KDL::Frame pose;
  if (port.read(pose) != core::FlowStatus::NewData) return;
  const KDL::Twist moved = KDL::diff(tool.anchor, pose);  // position and rotation (axis·angle) since the anchor
  if (!tool.seen || moved.vel.Norm() > tolerance_() || moved.rot.Norm() > angle_tolerance_()) {
    tool.anchor = pose;
    tool.since = now();
    tool.seen = true;
  }
}

bool RestMonitor::still(const Tool& tool) const noexcept {
  // Still since the ask at least: a tool that is only beginning to move as it is asked (the stick
  // let go of the thread a step before) has moved past the tolerance within the window.
  const auto since = std::max(tool.since, asked_at_);
  return tool.seen && std::chrono::duration<double>(now() - since).count() >= window_() - 1e-9;
}

void RestMonitor::updateHook() {
  watch(right_, right_tool_);
  watch(left_, left_tool_);
  if (ask_.take() && !asked_) {
    asked_ = true;
    asked_at_ = now();
  }
  if (asked_ && still(right_tool_) && still(left_tool_)) {
    asked_ = false;
    emitEvent("e_at_rest");
  }
}

}  // namespace cobra::components
