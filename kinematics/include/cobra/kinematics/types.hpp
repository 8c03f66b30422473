#pragma once
/// @file
/// Vocabulary shared by every solver of cobra::kinematics: the status of a real-time call, joint
/// types and limits, and the fixed-capacity set that analytic solvers write all their solutions
/// into. Units everywhere: m, rad (joint values: rad for revolute, m for prismatic joints).

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <kdl/jntarray.hpp>

namespace cobra::kinematics {

/// Result of a forward or inverse kinematics call. Real-time calls never throw: they return this,
/// and leave their output untouched unless the status is `Ok`.
enum class IkStatus {
  Ok,             ///< solved; the output holds the result
  Unreachable,    ///< the target is outside the workspace (no real solution exists)
  JointLimits,    ///< solutions exist, but none within the joint limits
  Singular,       ///< the configuration is singular and the result is not defined there
  NoConvergence,  ///< an iterative solver stopped before reaching the tolerance
  BadInput,       ///< wrong array size, or a value that is not finite
};

/// Stable lower-case name of `status` ("ok", "unreachable", ...), for logs and events.
const char* toString(IkStatus status) noexcept;

enum class JointType { Revolute, Prismatic };

/// "rad" for revolute, "m" for prismatic joints.
const char* unitOf(JointType type) noexcept;

/// Joint-space limits, one entry per joint: rad for revolute, m for prismatic joints.
struct JointLimits {
  std::vector<JointType> types;
  std::vector<double> lower;
  std::vector<double> upper;

  std::size_t size() const noexcept { return lower.size(); }
  /// True when every q[i] lies in [lower[i] - tolerance, upper[i] + tolerance]. Real-time safe.
  bool contains(std::span<const double> q, double tolerance = 0.0) const noexcept;
  bool contains(const KDL::JntArray& q, double tolerance = 0.0) const noexcept;
};

/// Checks `limits` for `robot` at construction time.
/// @throws std::invalid_argument naming the robot and the joint (1-based, as q1..qn in the thesis),
/// e.g. "UR5: joint 3 limits [2, 1] rad: min must be <= max", when the sizes differ from
/// `expected_joints`, a bound is not finite, or min > max.
void validateLimits(std::string_view robot, const JointLimits& limits, std::size_t expected_joints);

/// Limits of `joints` revolute joints, all [lower, upper] rad.
JointLimits revoluteLimits(std::size_t joints, double lower, double upper);

/// Formats a double for error messages (shortest round-trip form, "2" rather than "2.000000").
std::string formatNumber(double value);

/// All the solutions of an analytic inverse kinematics call, in fixed storage: filling it never
/// allocates. Each solution has `jointCount()` values (rad/m).
class IkSolutionSet {
 public:
  static constexpr std::size_t kMaxSolutions = 8;
  static constexpr std::size_t kMaxJoints = 8;

  /// Empties the set and fixes the number of joints of the solutions to come.
  void reset(std::size_t joints) noexcept;
  /// Appends one solution (`q.size()` must equal `jointCount()`); false when the set is full.
  bool push(std::span<const double> q) noexcept;
  std::size_t size() const noexcept { return count_; }
  bool empty() const noexcept { return count_ == 0; }
  std::size_t jointCount() const noexcept { return joints_; }
  std::span<const double> operator[](std::size_t i) const noexcept { return {solutions_[i].data(), joints_}; }
  /// Copies solution `i` into `q` (resized only when its size differs).
  void copyTo(std::size_t i, KDL::JntArray& q) const;

 private:
  std::array<std::array<double, kMaxJoints>, kMaxSolutions> solutions_{};
  std::size_t count_ = 0;
  std::size_t joints_ = 0;
};

/// Chooses among `solutions` the one nearest to `seed` and writes it into `out` (same size as
/// `seed`, untouched unless Ok). Each revolute joint of each solution is first moved by a multiple
/// of 2π to the value inside its limits nearest to the seed (a UR5 joint spans ±2π: the same pose
/// has two joint values); a solution none of whose representatives fits the limits is discarded.
/// Distance: sum of squared joint differences. Returns Unreachable when `solutions` is empty,
/// JointLimits when every solution violates the limits. Real-time safe: no allocation.
IkStatus selectNearest(const IkSolutionSet& solutions, const JointLimits& limits, const KDL::JntArray& seed,
                       KDL::JntArray& out) noexcept;

/// Moves the revolute joints of `q` by multiples of 2π to the values inside `limits` nearest to
/// `seed`; false (q partly changed) when some joint has no representative inside its limits.
bool wrapIntoLimits(std::span<double> q, const JointLimits& limits, std::span<const double> seed) noexcept;

/// `angle` wrapped into (-π, π].
double wrapToPi(double angle) noexcept;

}  // namespace cobra::kinematics
