#include "cobra/components/monitoring/contact_monitor.hpp"

#include <cmath>

namespace cobra::components {

ContactMonitor::ContactMonitor(std::string name)
    : Component(std::move(name), core::Role::Decision,
                "Contact events of a compliant tool: contact made / lost, off / back on its nominal path, force over "
                "its limit") {
  addProperty(contact_force_);
  addProperty(release_force_);
  addProperty(release_time_);
  addProperty(max_force_);
  addProperty(off_path_);
  addProperty(on_path_);
  addPort(wrench_);
  addPort(meas_pose_);
  addPort(nominal_pose_);
}

bool ContactMonitor::configureHook() {
  const auto n = [](double v) { return std::to_string(v); };
  if (!(contact_force_() > 0.0) || !(release_force_() >= 0.0) || !(release_force_() <= contact_force_()))
    return refuse("properties contact_force (" + n(contact_force_()) + " N) and release_force (" + n(release_force_()) +
                  " N): expected 0 <= release_force <= contact_force, contact_force > 0");
  if (!(max_force_() > contact_force_()))
    return refuse("property max_force (" + n(max_force_()) + " N): expected > contact_force (" + n(contact_force_()) +
                  " N)");
  if (!(release_time_() >= 0.0)) return refuse("property release_time (" + n(release_time_()) + " s): expected >= 0");
  if (!(on_path_() > 0.0) || !(off_path_() > on_path_()))
    return refuse("properties on_path_distance (" + n(on_path_()) + " m) and off_path_distance (" + n(off_path_()) +
                  " m): expected 0 < on_path_distance < off_path_distance");
  have_measured_ = have_nominal_ = false;
  in_contact_ = over_limit_ = off_path_state_ = false;
  below_since_ns_ = -1;
  return true;
}

void ContactMonitor::watchForce(double force) {
  if (!in_contact_ && force > contact_force_()) {
    in_contact_ = true;
    emitEvent("e_contact");
  } else if (in_contact_ && force < release_force_()) {
    const std::int64_t now_ns = now().count();
    if (below_since_ns_ < 0) below_since_ns_ = now_ns;
    if (static_cast<double>(now_ns - below_since_ns_) >= release_time_() * 1e9) {
      in_contact_ = false;
      below_since_ns_ = -1;
      emitEvent("e_contact_lost");
    }
  } else {
    below_since_ns_ = -1;
  }
  if (!over_limit_ && force > max_force_()) {
    over_limit_ = true;
    emitEvent("e_force_over_limit");
  } else if (over_limit_ && force < release_force_()) {
    over_limit_ = false;
  }
}

void ContactMonitor::watchPath(double distance) {
  if (!off_path_state_ && distance > off_path_()) {
    off_path_state_ = true;
    emitEvent("e_off_path");
  } else if (off_path_state_ && distance < on_path_()) {
    off_path_state_ = false;
    emitEvent("e_on_path");
  }
}

void ContactMonitor::updateHook() {
  KDL::Wrench wrench;
  if (wrench_.read(wrench) == core::FlowStatus::NewData) watchForce(wrench.force.Norm());
  const bool new_measured = meas_pose_.read(measured_) == core::FlowStatus::NewData;
  const bool new_nominal = nominal_pose_.read(nominal_) == core::FlowStatus::NewData;
  have_measured_ = have_measured_ || new_measured;
  have_nominal_ = have_nominal_ || new_nominal;
  if ((new_measured || new_nominal) && have_measured_ && have_nominal_)
    watchPath((measured_.p - nominal_.p).Norm());
}

}  // namespace cobra::components
