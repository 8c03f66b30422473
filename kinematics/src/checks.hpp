#pragma once
// Construction-time checks shared by the solvers (internal header, not installed).

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cobra/kinematics/types.hpp"

namespace cobra::kinematics::detail {

/// @throws std::invalid_argument "<robot>: parameter <name> is <value>: give a finite value in <unit>".
inline void requireFinite(std::string_view robot, std::string_view name, double value, std::string_view unit) {
  if (std::isfinite(value)) return;
  throw std::invalid_argument(std::string(robot) + ": parameter " + std::string(name) + " is " + formatNumber(value) +
                              ": give a finite value in " + std::string(unit));
}

/// requireFinite, and `value` != 0 (the closed form divides by it).
inline void requireNonZero(std::string_view robot, std::string_view name, double value, std::string_view unit) {
  requireFinite(robot, name, value, unit);
  if (value != 0.0) return;
  throw std::invalid_argument(std::string(robot) + ": parameter " + std::string(name) + " is 0 " + std::string(unit) +
                              ": the closed-form solution needs it non-zero");
}

/// validateLimits, and every joint revolute.
inline void requireRevolute(std::string_view robot, const JointLimits& limits, std::size_t joints) {
  validateLimits(robot, limits, joints);
  for (const JointType type : limits.types) {
    if (type != JointType::Revolute)
      throw std::invalid_argument(std::string(robot) + ": every joint is revolute: give JointType::Revolute limits");
  }
}

/// acos of a cosine computed from lengths: values within `tolerance` outside [-1, 1] are rounding
/// and clamped; beyond, returns false (no real solution).
inline bool clampedAcos(double c, double& angle, double tolerance = 1e-10) noexcept {
  if (c > 1.0 + tolerance || c < -1.0 - tolerance || !std::isfinite(c)) return false;
  angle = std::acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
  return true;
}

/// Branch bits of the 6R arms with a shoulder offset and a spherical-like wrist (UR, Puma).
inline constexpr std::uint8_t kShoulderBit = 1;
inline constexpr std::uint8_t kElbowBit = 2;
inline constexpr std::uint8_t kWristBit = 4;

/// Sets branch bit `bit` when `value` < 0, and marks it ambiguous when |value| < kBranchMargin
/// (the configuration is on the singular boundary between the two choices).
inline void chooseBranch(IkBranch& branch, std::uint8_t bit, double value) noexcept {
  if (value < 0.0) branch.bits = static_cast<std::uint8_t>(branch.bits | bit);
  if (std::abs(value) < kBranchMargin) branch.ambiguous = static_cast<std::uint8_t>(branch.ambiguous | bit);
}

}  // namespace cobra::kinematics::detail
