#pragma once
/// @file
/// Vocabulary shared by every solver of cobra::kinematics: the status of a real-time call, joint
/// types and limits, and the fixed-capacity set that analytic solvers write all their solutions
/// into. Units everywhere: m, rad (joint values: rad for revolute, m for prismatic joints).

#include <array>
#include <cstddef>
#include <cstdint>
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
  /// solutions exist, but none on the current configuration's branch that the joints can reach
  /// within one period at their velocity limits (see ContinuousIk, continuity.hpp)
  Discontinuous,
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

/// Which family of inverse kinematics solutions ("branch") a configuration belongs to: bit i is one
/// binary choice of a closed form (UR5 and Puma: bit 0 shoulder, bit 1 elbow, bit 2 wrist; I-SUR:
/// bit 0 the pitch representation). Two configurations on the same branch are joined by a joint
/// path that crosses no singular configuration. `ambiguous` marks the choices a configuration sits
/// on the boundary of (within kBranchMargin of a singular configuration): either value is
/// compatible there. A solver without branches leaves both 0: everything is compatible.
struct IkBranch {
  std::uint8_t bits = 0;
  std::uint8_t ambiguous = 0;

  /// A branch compatible with every other (no choice made): what `KinematicsSolver::inverse` uses.
  static constexpr IkBranch any() noexcept { return IkBranch{0, 0xFF}; }
  /// True when no choice defined in both differs.
  constexpr bool compatibleWith(IkBranch other) const noexcept {
    return ((bits ^ other.bits) & ~(ambiguous | other.ambiguous)) == 0;
  }
  constexpr bool operator==(const IkBranch&) const noexcept = default;
};

/// Distance to a singular configuration below which a branch choice is ambiguous: for sines of
/// joint angles (dimensionless, ~ rad near 0) and for the shoulder's lateral distance (m).
inline constexpr double kBranchMargin = 1e-9;

/// All the solutions of an analytic inverse kinematics call, in fixed storage: filling it never
/// allocates. Each solution has `jointCount()` values (rad/m).
class IkSolutionSet {
 public:
  static constexpr std::size_t kMaxSolutions = 8;
  static constexpr std::size_t kMaxJoints = 8;

  /// Empties the set and fixes the number of joints of the solutions to come.
  void reset(std::size_t joints) noexcept;
  /// Appends one solution (`q.size()` must equal `jointCount()`) and the branch it lies on; false
  /// when the set is full.
  bool push(std::span<const double> q, IkBranch branch = IkBranch{}) noexcept;
  std::size_t size() const noexcept { return count_; }
  bool empty() const noexcept { return count_ == 0; }
  std::size_t jointCount() const noexcept { return joints_; }
  std::span<const double> operator[](std::size_t i) const noexcept { return {solutions_[i].data(), joints_}; }
  /// The branch solution `i` lies on (as the solver's `branch` would compute it from its joints).
  IkBranch branch(std::size_t i) const noexcept { return branches_[i]; }
  /// Copies solution `i` into `q` (resized only when its size differs).
  void copyTo(std::size_t i, KDL::JntArray& q) const;

 private:
  std::array<std::array<double, kMaxJoints>, kMaxSolutions> solutions_{};
  std::array<IkBranch, kMaxSolutions> branches_{};
  std::size_t count_ = 0;
  std::size_t joints_ = 0;
};

/// Chooses among `solutions` the one nearest to `seed` whose branch is compatible with `branch`,
/// and writes it into `out` (same size as `seed`, untouched unless Ok). Each revolute joint of each
/// solution is first moved by a multiple of 2π to the value inside its limits nearest to the seed
/// (a UR5 joint spans ±2π: the same pose has two joint values); a solution none of whose
/// representatives fits the limits is discarded. Distance: sum of squared joint differences.
/// Returns Unreachable when `solutions` is empty, JointLimits when every solution violates the
/// limits, Discontinuous when some fit the limits but none is on `branch`. Real-time safe: no
/// allocation.
IkStatus selectNearest(const IkSolutionSet& solutions, const JointLimits& limits, const KDL::JntArray& seed,
                       KDL::JntArray& out, IkBranch branch = IkBranch::any()) noexcept;

/// Moves the revolute joints of `q` by multiples of 2π to the values inside `limits` nearest to
/// `seed`; false (q partly changed) when some joint has no representative inside its limits.
bool wrapIntoLimits(std::span<double> q, const JointLimits& limits, std::span<const double> seed) noexcept;

/// `angle` wrapped into (-π, π].
double wrapToPi(double angle) noexcept;

}  // namespace cobra::kinematics
