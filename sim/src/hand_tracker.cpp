#include "cobra/sim/hand_tracker.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::sim {
namespace {

constexpr double kPi = 3.141592653589793;

[[noreturn]] void reject(const char* parameter, double value, const char* expected) {
  throw std::invalid_argument(std::string("hand tracker: ") + parameter + " = " + std::to_string(value) +
                              ", expected " + expected);
}

}  // namespace

void validate(const HandTrackerModel& m) {
  if (!std::isfinite(m.frame_rate) || m.frame_rate <= 0) reject("frame_rate", m.frame_rate, "> 0 frames/s");
  if (!std::isfinite(m.fov_x) || m.fov_x <= 0 || m.fov_x >= kPi) reject("fov_x", m.fov_x, "in (0, pi) rad");
  if (!std::isfinite(m.fov_y) || m.fov_y <= 0 || m.fov_y >= kPi) reject("fov_y", m.fov_y, "in (0, pi) rad");
  if (!std::isfinite(m.min_height) || m.min_height < 0) reject("min_height", m.min_height, ">= 0 m");
  if (!std::isfinite(m.max_height) || m.max_height <= m.min_height)
    reject("max_height", m.max_height, "> min_height m");
  if (!std::isfinite(m.position_noise) || m.position_noise < 0) reject("position_noise", m.position_noise, ">= 0 m");
}

HandTracker::HandTracker(const HandTrackerModel& model, std::uint64_t seed) : model_(model), noise_(seed) {
  validate(model_);
  tan_half_x_ = std::tan(model_.fov_x / 2);
  tan_half_y_ = std::tan(model_.fov_y / 2);
}

bool HandTracker::inFieldOfView(const KDL::Vector& p) const noexcept {
  const double z = p.z();
  return z >= model_.min_height && z <= model_.max_height && std::abs(p.x()) <= z * tan_half_x_ &&
         std::abs(p.y()) <= z * tan_half_y_;
}

void HandTracker::track(bool present, const KDL::Frame& truth, TrackedHand& out) noexcept {
  out.valid = present && inFieldOfView(truth.p);
  if (!out.valid) return;
  const double s = model_.position_noise;
  const double nx = noise_.sample(), ny = noise_.sample(), nz = noise_.sample();  // fixed order: reproducible
  out.pose = KDL::Frame(truth.M, truth.p + KDL::Vector(s * nx, s * ny, s * nz));
}

bool HandTracker::step(double dt, bool right_present, const KDL::Frame& right, bool left_present,
                       const KDL::Frame& left) noexcept {
  if (!std::isfinite(dt) || dt <= 0) return false;
  const double period = 1.0 / model_.frame_rate;
  since_frame_ += dt;
  if (since_frame_ + 1e-12 < period) return false;
  since_frame_ = std::fmod(since_frame_ + 1e-12, period);
  ++frame_.id;
  track(right_present, right, frame_.right);
  track(left_present, left, frame_.left);
  return true;
}

}  // namespace cobra::sim
