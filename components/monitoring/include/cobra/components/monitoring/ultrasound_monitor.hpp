#pragma once
/// @file
/// Situation awareness for the ultrasound guidance (thesis §4.2): needle visible / lost, probe in
/// contact / lost contact, as events.

#include <cstdint>
#include <string>

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Decision component for the ultrasound image (thesis §4.2: the needle is guided in the image of
/// a probe pressed on the skin). Inputs: `needlePlaneDistance` (m), `needleInImage` (0/1; taken
/// as 1 until a value arrives), `probeContactForce` (N) — PatientSimulator's outputs, or an image
/// processing component's and the probe sensor's on the real set-up.
/// Events, edge-triggered with hysteresis: `e_probe_contact` when the force rises above
/// `contact_force` (N), `e_probe_contact_lost` when it stays below `contact_lost_force` (N) for
/// `contact_lost_time` (s; 0: at once; a transient dip, e.g. while the probe's reference is moved,
/// is not a loss);
/// `e_needle_visible` when in contact, in the image and closer than `visible_distance` (m) to the
/// plane, `e_needle_lost` when contact is lost, the tip leaves the image or the distance exceeds
/// `lost_distance` (m). updateHook allocates nothing.
class UltrasoundMonitor : public core::Component {
 public:
  explicit UltrasoundMonitor(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  core::Property<double> visible_distance_{"visible_distance", 0.002, "m",
                                           "plane distance below which the needle is seen"};
  core::Property<double> lost_distance_{"lost_distance", 0.003, "m",
                                        "plane distance above which it is lost, >= visible"};
  core::Property<double> contact_force_{"contact_force", 2.0, "N", "probe force meaning contact"};
  core::Property<double> contact_lost_force_{"contact_lost_force", 1.0, "N",
                                             "probe force meaning contact lost, <= contact"};
  core::Property<double> contact_lost_time_{"contact_lost_time", 0.0, "s",
                                            "how long the force must stay below contact_lost_force, >= 0"};

  core::InputPort<double> plane_distance_{"needlePlaneDistance", "needle distance to the imaging plane", "m"};
  core::InputPort<double> in_image_{"needleInImage", "1 when the tip is within the image", "1"};
  core::InputPort<double> contact_{"probeContactForce", "probe force on the skin", "N"};

  bool in_contact_ = false, visible_ = false;
  /// Since when the force is below contact_lost_force while in contact (ns; -1: it is not).
  std::int64_t below_since_ns_ = -1;
};

}  // namespace cobra::components
