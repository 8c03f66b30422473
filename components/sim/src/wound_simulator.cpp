#include "cobra/components/sim/wound_simulator.hpp"

#include <algorithm>

namespace cobra::components {
namespace {

/// The wrench of `force` (N, world axes) applied at a tip `lever` m (world axes) from a frame's
/// origin, about that origin: torque = lever × force (N·m).
KDL::Wrench atPortFrame(const KDL::Vector& force, const KDL::Vector& lever) noexcept {
  return {force, lever * force};
}

}  // namespace

WoundSimulator::WoundSimulator(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "Simulated suturing patient (thesis ch. 5): a planar wound the Endo Stitch stitches, the thread it "
                "pulls closed, the stick that hooks it, and the wound's edges for stitch planning") {
  for (auto* p : {&max_gap_, &tissue_stiffness_, &closure_spread_, &bite_, &stitch_depth_, &stitch_tolerance_,
                  &closed_gap_, &thread_length_, &thread_slack_, &thread_stiffness_, &breaking_tension_, &hook_radius_,
                  &release_time_})
    addProperty(*p);
  addProperty(cut_);
  addProperty(wound_pose_);
  addProperty(tool_tip_offset_);
  addProperty(edge_samples_);
  addProperty(release_event_);
  addPort(tool_tip_);
  addPort(stick_tip_);
  addPort(actuations_);
  addEventPort(input_events_);
  addPort(tension_);
  addPort(tool_wrench_);
  addPort(stick_wrench_);
  addPort(stitch_count_);
  addPort(max_stitch_gap_);
  addPort(max_gap_out_);
  addPort(miss_reason_);
  addPort(miss_distance_);
  addPort(edges_);
  addPort(thread_path_);
  addPort(stitch_lines_);
}

bool WoundSimulator::configureHook() {
  const std::vector<double>& cut = cut_();
  if (cut.size() < 4 || cut.size() % 2 != 0)
    return refuse("property cut has " + std::to_string(cut.size()) +
                  " numbers; expected x, y pairs (m) of at least 2 points of the cut's centreline");
  if (edge_samples_() < 2)
    return refuse("property edge_samples is " + std::to_string(edge_samples_()) + "; expected at least 2");
  if (release_event_().empty() || release_event_().size() > core::BoundedString<63>::capacity())
    return refuse("property release_event is '" + release_event_() + "'; expected an event name of 1 to 63 characters");
  sim::WoundModel wound;
  wound.cut.clear();
  for (std::size_t i = 0; i < cut.size(); i += 2) wound.cut.emplace_back(cut[i], cut[i + 1], 0.0);
  wound.max_gap = max_gap_();
  wound.tissue_stiffness = tissue_stiffness_();
  wound.closure_spread = closure_spread_();
  wound.bite = bite_();
  wound.stitch_depth = stitch_depth_();
  wound.stitch_tolerance = stitch_tolerance_();
  wound.closed_gap = closed_gap_();
  sim::ThreadModel thread;
  thread.length = thread_length_();
  thread.slack = thread_slack_();
  thread.stiffness = thread_stiffness_();
  thread.breaking_tension = breaking_tension_();
  thread.hook_radius = hook_radius_();
  thread.release_time = release_time_();
  try {
    wound_.emplace(std::move(wound), thread);
  } catch (const std::exception& e) {
    return refuse(e.what());  // names the parameter and its range
  }
  world_to_wound_ = wound_pose_().Inverse();
  release_name_.assign(release_event_());
  edge_buffer_.assign(static_cast<std::size_t>(edge_samples_()) * 6, 0.0);
  edges_.setDataSample(edge_buffer_);
  const auto stitches = static_cast<std::size_t>(wound_->model().max_stitches);
  thread_buffer_.assign(3 * (2 * stitches + 2), 0.0);  // two skin points per stitch, the bend, the tip
  thread_path_.setDataSample(thread_buffer_);
  stitch_buffer_.assign(6 * 3 * stitches, 0.0);  // three segments per complete stitch
  stitch_lines_.setDataSample(stitch_buffer_);
  thread_buffer_.clear();
  stitch_buffer_.clear();
  return true;
}

bool WoundSimulator::startHook() {
  have_tool_ = have_stick_ = hooked_ = broken_ = false;
  tool_lever_ = KDL::Vector::Zero();
  last_update_ns_ = -1;
  actuations_seen_ = 0;
  core::Event stale;
  while (input_events_.readNew(stale) == core::FlowStatus::NewData) {
  }  // requests sent before the start are not this run's
  publish(true);
  return true;
}

void WoundSimulator::cleanupHook() { wound_.reset(); }

void WoundSimulator::actuate() noexcept {
  if (!have_tool_) {
    miss_reason_.write(static_cast<int>(sim::StitchMiss::OutsideWound));
    emitEvent("e_stitch_missed");
    return;
  }
  const sim::StitchResult r = wound_->actuate(wound_->sideAt(tool_), tool_);
  if (r.applied()) {
    emitEvent("e_stitch_applied");
    return;
  }
  miss_reason_.write(static_cast<int>(r.miss));
  miss_distance_.write(r.distance);
  emitEvent("e_stitch_missed");
}

void WoundSimulator::updateHook() {
  KDL::Frame pose;
  if (tool_tip_.read(pose) != core::FlowStatus::NoData) {
    tool_lever_ = pose.M * tool_tip_offset_().p;
    tool_ = world_to_wound_ * (pose.p + tool_lever_);
    have_tool_ = true;
  }
  if (stick_tip_.read(pose) != core::FlowStatus::NoData) {
    stick_ = world_to_wound_ * pose.p;
    have_stick_ = true;
  }
  int count = 0;
  if (actuations_.read(count) == core::FlowStatus::NewData) {
    if (count < actuations_seen_) actuations_seen_ = count;  // the robot restarted its count
    for (; actuations_seen_ < count; ++actuations_seen_) actuate();
  }
  core::Event request;
  while (input_events_.readNew(request) == core::FlowStatus::NewData) {
    if (request.name == release_name_) wound_->releaseThread();
  }
  const std::int64_t now_ns = now().count();
  const double dt = last_update_ns_ < 0 ? 0.0 : static_cast<double>(now_ns - last_update_ns_) * 1e-9;  // s
  last_update_ns_ = now_ns;
  if (have_tool_ && have_stick_) wound_->step(tool_, stick_, dt);
  if (wound_->hooked() && !hooked_) emitEvent("e_thread_hooked");
  hooked_ = wound_->hooked();
  if (wound_->broken() && !broken_) emitEvent("e_thread_broken");
  broken_ = wound_->broken();
  publish(false);
}

void WoundSimulator::publish(bool all) noexcept {
  const sim::Wound& w = *wound_;
  if (all || w.revision() != published_revision_) {  // the gap changed: recompute what depends on it
    published_revision_ = w.revision();
    complete_ = 0;
    widest_stitch_gap_ = 0.0;
    for (int i = 0; i < static_cast<int>(w.stitches().size()); ++i) {
      if (w.stitches()[static_cast<std::size_t>(i)].complete()) ++complete_;
      widest_stitch_gap_ = std::max(widest_stitch_gap_, w.stitchGap(i));
    }
    widest_gap_ = w.maxGap();
    const KDL::Frame& to_world = wound_pose_();
    const std::size_t samples = edge_buffer_.size() / 6;
    for (std::size_t i = 0; i < samples; ++i) {
      const double s = w.length() * static_cast<double>(i) / static_cast<double>(samples - 1);
      const KDL::Vector right = to_world * w.edgePoint(sim::WoundSide::Right, s, 0.0);
      const KDL::Vector left = to_world * w.edgePoint(sim::WoundSide::Left, s, 0.0);
      double* out = &edge_buffer_[i * 6];
      out[0] = right.x(), out[1] = right.y(), out[2] = right.z();
      out[3] = left.x(), out[4] = left.y(), out[5] = left.z();
    }
  }
  // Written every step (a reader connected later gets them too); recomputed only above.
  tension_.write(w.tension());
  const KDL::Rotation& to_world = wound_pose_().M;
  tool_wrench_.write(atPortFrame(to_world * w.toolForce(), tool_lever_));
  // stickTipPose is the stick's tip itself (the left tool frame, apps/suturing/frames.lua): no lever.
  stick_wrench_.write(KDL::Wrench(to_world * w.stickForce(), KDL::Vector::Zero()));
  stitch_count_.write(complete_);
  max_stitch_gap_.write(widest_stitch_gap_);
  max_gap_out_.write(widest_gap_);
  edges_.write(edge_buffer_);
  publishThread();
}

void WoundSimulator::publishThread() noexcept {
  const sim::Wound& w = *wound_;
  const KDL::Frame& to_world = wound_pose_();
  const auto put = [&to_world](std::vector<double>& out, const KDL::Vector& wound_point) {
    const KDL::Vector p = to_world * wound_point;
    out.insert(out.end(), {p.x(), p.y(), p.z()});  // within the capacity reserved at configure
  };
  thread_buffer_.clear();
  stitch_buffer_.clear();
  const auto& stitches = w.stitches();
  for (int i = 0; i < static_cast<int>(stitches.size()); ++i) {
    const sim::Stitch& st = stitches[static_cast<std::size_t>(i)];
    for (const sim::WoundSide side : {sim::WoundSide::Right, sim::WoundSide::Left}) {
      if (!(side == sim::WoundSide::Right ? st.right : st.left)) continue;
      put(thread_buffer_, w.skinPoint(i, side));
      put(stitch_buffer_, w.skinPoint(i, side));
      put(stitch_buffer_, w.stitchPoint(side, st.s));
    }
    if (st.complete()) {
      put(stitch_buffer_, w.stitchPoint(sim::WoundSide::Right, st.s));
      put(stitch_buffer_, w.stitchPoint(sim::WoundSide::Left, st.s));
    }
  }
  if (!stitches.empty() && !w.broken()) {
    if (w.hooked()) put(thread_buffer_, w.hookPoint());
    if (have_tool_) put(thread_buffer_, tool_);
  }
  thread_path_.write(thread_buffer_);
  stitch_lines_.write(stitch_buffer_);
}

}  // namespace cobra::components
