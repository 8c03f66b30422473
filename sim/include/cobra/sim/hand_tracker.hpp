#pragma once
/// @file
/// An optical hand tracker like the Leap Motion (thesis §5.3.3: two IR cameras, 200 fps, USB):
/// frames at a fixed rate, a field of view shaped as a pyramid above the device between a minimum
/// and a maximum height, Gaussian position noise, and hands that are lost outside the field of
/// view. The true hand poses are inputs (a scripted surgeon). Device frame L: origin at the device
/// centre, z up out of the device, x along its long side; metres and radians.

#include <cstdint>
#include <kdl/frames.hpp>

#include "cobra/fieldbus/hand_tracker_device.hpp"
#include "cobra/sim/gaussian_noise.hpp"

namespace cobra::sim {

/// Tracker description. Field-of-view values are ASSUMPTIONS after Leap Motion's public figures
/// for the original controller (150° wide along the long side, 120° deep, about 25-600 mm above
/// the device); the noise is an ASSUMPTION of the order of the sub-millimetre static accuracy
/// reported by Weichert et al., Sensors 13(5), 2013.
struct HandTrackerModel {
  double frame_rate = 200.0;                         ///< frames per second, > 0 (thesis: 200 fps)
  double fov_x = 150.0 * 3.141592653589793 / 180.0;  ///< rad, in (0, π): full angle in the x-z plane
  double fov_y = 120.0 * 3.141592653589793 / 180.0;  ///< rad, in (0, π): full angle in the y-z plane
  double min_height = 0.025;                         ///< m, >= 0: nothing is seen closer to the device
  double max_height = 0.6;                           ///< m, > min_height
  double position_noise = 5e-4;                      ///< m, >= 0: standard deviation per axis
};

/// @throws std::invalid_argument naming the parameter and the expected range.
void validate(const HandTrackerModel& model);

/// The frame types are the device interface's (fieldbus/hand_tracker_device.hpp): what the
/// tracker produces is what a driver receives.
using TrackedHand = fieldbus::TrackedHand;
using HandFrame = fieldbus::HandFrame;

/// The tracker: `step(dt, ...)` advances time by dt (s) and returns true when a new frame was
/// taken in that interval (at most one per call is reported: the latest). noexcept, no allocation;
/// identical seeds and inputs give identical frames.
class HandTracker {
 public:
  /// @throws std::invalid_argument when the model is invalid.
  explicit HandTracker(const HandTrackerModel& model, std::uint64_t seed = 0);

  /// @param right_present / left_present whether the hand is above the device at all
  /// @param right / left true hand poses (m, frame L)
  bool step(double dt, bool right_present, const KDL::Frame& right, bool left_present, const KDL::Frame& left) noexcept;

  /// True when `position` (m, frame L) is inside the field of view.
  bool inFieldOfView(const KDL::Vector& position) const noexcept;
  const HandFrame& frame() const noexcept { return frame_; }
  const HandTrackerModel& model() const noexcept { return model_; }

 private:
  void track(bool present, const KDL::Frame& truth, TrackedHand& out) noexcept;

  HandTrackerModel model_;
  GaussianNoise noise_;
  double since_frame_ = 0.0;  // s since the last frame
  double tan_half_x_ = 0.0, tan_half_y_ = 0.0;
  HandFrame frame_;
};

}  // namespace cobra::sim
