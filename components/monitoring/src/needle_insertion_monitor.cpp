#include "cobra/components/monitoring/needle_insertion_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace cobra::components {
namespace {

constexpr std::size_t kCapsuleValues = 7;

/// Distance (m) of p to the segment a-b.
double segmentDistance(const double* capsule, const KDL::Vector& p) noexcept {
  const KDL::Vector a(capsule[0], capsule[1], capsule[2]);
  const KDL::Vector ab = KDL::Vector(capsule[3], capsule[4], capsule[5]) - a;
  const double len2 = KDL::dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(KDL::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + ab * s)).Norm();
}

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

NeedleInsertionMonitor::NeedleInsertionMonitor(std::string name)
    : Component(std::move(name), core::Role::Decision,
                "Needle insertion events: skin touched/penetrated, target reached, force over threshold, forbidden "
                "region, needle trapped/free") {
  addProperty(needle_axis_);
  addProperty(contact_force_);
  addProperty(puncture_min_peak_);
  addProperty(puncture_drop_);
  addProperty(puncture_drop_time_);
  addProperty(target_tolerance_);
  addProperty(max_force_);
  addProperty(forbidden_regions_);
  addProperty(forbidden_margin_);
  addProperty(forbidden_hysteresis_);
  addProperty(extraction_threshold_);
  addProperty(release_force_);
  addPort(meas_wrench_);
  addPort(meas_cart_pose_);
  addPort(target_pose_);
  addOperation("reset", std::function<void()>([this] { reset_request_.ask(activity()); }),
               "re-arms e_skin_touched and e_skin_penetrated for a new insertion, in this component's next step",
               core::ExecutionThread::Client);
}

bool NeedleInsertionMonitor::configureHook() {
  const double norm = needle_axis_().Norm();
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-6)
    return refuse("property needle_axis has length " + std::to_string(norm) + "; give a unit vector");
  const struct {
    const core::Property<double>& p;
  } positives[] = {{contact_force_}, {puncture_min_peak_},    {puncture_drop_time_}, {target_tolerance_},
                   {max_force_},     {extraction_threshold_}, {release_force_}};
  for (const auto& entry : positives)
    if (!positive(entry.p()))
      return refuse("property " + entry.p.name() + " is " + std::to_string(entry.p()) + " " + entry.p.unit() +
                    "; expected > 0 " + entry.p.unit());
  if (!(puncture_drop_() > 0.0 && puncture_drop_() < 1.0))
    return refuse("property puncture_drop is " + std::to_string(puncture_drop_()) + "; expected a fraction in (0, 1)");
  if (!(release_force_() < extraction_threshold_()))
    return refuse("property release_force (" + std::to_string(release_force_()) +
                  " N) must be below extraction_threshold (" + std::to_string(extraction_threshold_()) + " N)");
  if (!(forbidden_margin_() >= 0.0) || !(forbidden_hysteresis_() >= 0.0))
    return refuse("properties forbidden_margin and forbidden_hysteresis must be >= 0 m");
  const std::vector<double>& regions = forbidden_regions_();
  if (regions.size() % kCapsuleValues != 0)
    return refuse("property forbidden_regions has " + std::to_string(regions.size()) +
                  " numbers; give 7 per capsule (ax, ay, az, bx, by, bz, radius in m)");
  for (std::size_t i = 0; i < regions.size(); i += kCapsuleValues)
    if (!positive(regions[i + 6]))
      return refuse("property forbidden_regions: capsule " + std::to_string(i / kCapsuleValues + 1) + " has radius " +
                    std::to_string(regions[i + 6]) + " m; expected > 0 m");
  axis_ = needle_axis_();
  reset();
  over_force_ = trapped_ = at_target_ = in_forbidden_ = have_target_ = false;
  return true;
}

void NeedleInsertionMonitor::reset() {
  touched_ = penetrated_ = false;
  peak_ = 0.0;
  peak_ns_ = 0;
}

void NeedleInsertionMonitor::checkForce(const KDL::Wrench& wrench, std::int64_t now_ns) noexcept {
  const double axial = -KDL::dot(wrench.force, axis_);
  if (!touched_ && axial > contact_force_()) {
    touched_ = true;
    emitEvent("e_skin_touched");
  }
  if (touched_ && !penetrated_) {
    if (axial > peak_) {
      peak_ = axial;
      peak_ns_ = now_ns;
    } else if (peak_ >= puncture_min_peak_() && axial < (1.0 - puncture_drop_()) * peak_) {
      if (static_cast<double>(now_ns - peak_ns_) * 1e-9 <= puncture_drop_time_()) {
        penetrated_ = true;
        emitEvent("e_skin_penetrated");
      } else {
        peak_ = axial;  // a slow decrease: the robot backed off; look for a new peak
        peak_ns_ = now_ns;
      }
    }
  }
  const double magnitude = wrench.force.Norm();
  if (!over_force_ && magnitude > max_force_()) {
    over_force_ = true;
    emitEvent("e_force_over_threshold");
  } else if (over_force_ && magnitude < 0.8 * max_force_()) {
    over_force_ = false;
  }
  const double extraction = std::max(0.0, -axial);
  if (!trapped_ && extraction > extraction_threshold_()) {
    trapped_ = true;
    emitEvent("e_needle_trapped");
  } else if (trapped_ && extraction < release_force_()) {
    trapped_ = false;
    emitEvent("e_needle_free");
  }
}

void NeedleInsertionMonitor::checkPose(const KDL::Frame& tip) noexcept {
  if (have_target_) {
    const double distance = (tip.p - target_.p).Norm();
    if (!at_target_ && distance < target_tolerance_()) {
      at_target_ = true;
      emitEvent("e_target_reached");
    } else if (at_target_ && distance > 2.0 * target_tolerance_()) {
      at_target_ = false;
    }
  }
  const std::vector<double>& regions = forbidden_regions_();
  double clearance = INFINITY;  // m, distance outside the nearest capsule's surface
  for (std::size_t i = 0; i + kCapsuleValues <= regions.size(); i += kCapsuleValues)
    clearance = std::min(clearance, segmentDistance(&regions[i], tip.p) - regions[i + 6]);
  if (!in_forbidden_ && clearance < forbidden_margin_()) {
    in_forbidden_ = true;
    emitEvent("e_forbidden_region");
  } else if (in_forbidden_ && clearance > forbidden_margin_() + forbidden_hysteresis_()) {
    in_forbidden_ = false;
  }
}

void NeedleInsertionMonitor::updateHook() {
  if (reset_request_.take()) reset();
  if (target_pose_.read(target_) != core::FlowStatus::NoData) have_target_ = true;
  KDL::Wrench wrench;
  if (meas_wrench_.read(wrench) == core::FlowStatus::NewData) checkForce(wrench, now().count());
  KDL::Frame tip;
  if (meas_cart_pose_.read(tip) == core::FlowStatus::NewData) checkPose(tip);
}

}  // namespace cobra::components
