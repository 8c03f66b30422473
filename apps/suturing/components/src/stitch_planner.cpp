#include "cobra/components/suturing/stitch_planner.hpp"

#include <cmath>
#include <functional>

namespace cobra::components {

StitchPlannerComponent::StitchPlannerComponent(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Stitch planning (thesis §5.2.1): the next stitch's right and left targets from the wound's current "
                "edges") {
  for (auto* p : {&spacing_, &end_margin_, &depth_, &closed_gap_}) addProperty(*p);
  addProperty(skin_normal_);
  addProperty(max_edge_samples_);
  addPort(edges_in_);
  addPort(right_);
  addPort(left_);
  addPort(index_);
  addPort(gap_);
  addPort(planned_);
  addOperation("askStitch", std::function<void()>([this] { ask_.ask(activity()); }),
               "plan the current stitch from the newest edges (answered by e_stitch_planned, e_stitches_done or "
               "e_no_wound_data)");
  addOperation("nextStitch", std::function<void()>([this] { next_.ask(activity()); }),
               "move past the last planned stitch");
  addOperation("restartPlan", std::function<void()>([this] { restart_.ask(activity()); }), "back to stitch 0");
}

bool StitchPlannerComponent::configureHook() {
  suturing::StitchPlanModel model;
  model.spacing = spacing_();
  model.end_margin = end_margin_();
  model.depth = depth_();
  model.closed_gap = closed_gap_();
  try {
    planner_ = suturing::StitchPlanner(model);
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
  if (std::abs(skin_normal_().Norm() - 1.0) > 1e-6)
    return refuse("property skin_normal has length " + std::to_string(skin_normal_().Norm()) +
                  "; expected a unit vector out of the skin (world frame)");
  if (max_edge_samples_() < 2)
    return refuse("property max_edge_samples is " + std::to_string(max_edge_samples_()) + "; expected at least 2");
  const auto capacity = static_cast<std::size_t>(max_edge_samples_());
  edges_.right.reserve(capacity);
  edges_.left.reserve(capacity);
  edges_.skin_normal = skin_normal_();
  samples_.reserve(capacity * 6);
  return true;
}

bool StitchPlannerComponent::startHook() {
  ask_.clear();
  next_.clear();
  restart_.clear();
  current_ = 0;
  last_planned_ = -1;
  return true;
}

void StitchPlannerComponent::updateHook() {
  (void)edges_in_.read(samples_);  // the newest edges, kept between requests
  if (restart_.take()) current_ = 0, last_planned_ = -1;
  if (next_.take() && last_planned_ >= current_) current_ = last_planned_ + 1;
  if (ask_.take()) answer();
}

void StitchPlannerComponent::answer() noexcept {
  const std::size_t points = samples_.size() / 6;
  if (samples_.size() % 6 != 0 || points < 2 || points > edges_.right.capacity()) {
    emitEvent("e_no_wound_data");
    return;
  }
  edges_.right.clear();
  edges_.left.clear();
  for (std::size_t i = 0; i < points; ++i) {
    const double* p = &samples_[i * 6];
    edges_.right.emplace_back(p[0], p[1], p[2]);
    edges_.left.emplace_back(p[3], p[4], p[5]);
  }
  if (!suturing::StitchPlanner::usable(edges_)) {
    emitEvent("e_no_wound_data");
    return;
  }
  planned_.write(planner_.count(edges_));
  suturing::StitchTarget target;
  if (!planner_.next(edges_, current_, target)) {
    emitEvent("e_stitches_done");
    return;
  }
  last_planned_ = target.index;
  right_.write(target.right);
  left_.write(target.left);
  index_.write(target.index);
  gap_.write(target.gap);
  emitEvent("e_stitch_planned");
}

}  // namespace cobra::components
