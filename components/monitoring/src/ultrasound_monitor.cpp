#include "cobra/components/monitoring/ultrasound_monitor.hpp"

#include <cmath>

namespace cobra::components {

UltrasoundMonitor::UltrasoundMonitor(std::string name)
    : Component(std::move(name), core::Role::Decision,
                "Ultrasound events: needle visible / lost, probe in contact / contact lost (with hysteresis)") {
  addProperty(visible_distance_);
  addProperty(lost_distance_);
  addProperty(contact_force_);
  addProperty(contact_lost_force_);
  addProperty(contact_lost_time_);
  addPort(plane_distance_);
  addPort(in_image_);
  addPort(contact_);
}

bool UltrasoundMonitor::configureHook() {
  if (!(visible_distance_() > 0.0) || !(lost_distance_() >= visible_distance_()))
    return refuse("properties visible_distance (" + std::to_string(visible_distance_()) + " m) and lost_distance (" +
                  std::to_string(lost_distance_()) + " m): expected 0 < visible_distance <= lost_distance");
  if (!(contact_lost_force_() >= 0.0) || !(contact_force_() >= contact_lost_force_()))
    return refuse("properties contact_force (" + std::to_string(contact_force_()) + " N) and contact_lost_force (" +
                  std::to_string(contact_lost_force_()) + " N): expected 0 <= contact_lost_force <= contact_force");
  if (!(contact_lost_time_() >= 0.0))
    return refuse("property contact_lost_time (" + std::to_string(contact_lost_time_()) + " s): expected >= 0");
  in_contact_ = visible_ = false;
  below_since_ns_ = -1;
  return true;
}

void UltrasoundMonitor::updateHook() {
  double force = 0.0;
  if (contact_.read(force) != core::FlowStatus::NoData) {
    if (!in_contact_ && force > contact_force_()) {
      in_contact_ = true;
      emitEvent("e_probe_contact");
    } else if (in_contact_ && force < contact_lost_force_()) {
      const std::int64_t now_ns = now().count();
      if (below_since_ns_ < 0) below_since_ns_ = now_ns;
      if (static_cast<double>(now_ns - below_since_ns_) >= contact_lost_time_() * 1e9) {
        in_contact_ = false;
        below_since_ns_ = -1;
        emitEvent("e_probe_contact_lost");
      }
    } else {
      below_since_ns_ = -1;
    }
  }
  double in_image = 1.0;
  (void)in_image_.read(in_image);
  double distance = INFINITY;
  (void)plane_distance_.read(distance);
  const bool seen = in_contact_ && in_image >= 0.5;
  if (!visible_ && seen && distance < visible_distance_()) {
    visible_ = true;
    emitEvent("e_needle_visible");
  } else if (visible_ && (!seen || distance > lost_distance_())) {
    visible_ = false;
    emitEvent("e_needle_lost");
  }
}

}  // namespace cobra::components
