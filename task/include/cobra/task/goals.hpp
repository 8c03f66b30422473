#pragma once
/// @file
/// The state table's evaluator (thesis §4.5.5): a row's goal pair and its goal alternatives with
/// their checks, from datums a Frame Generator resolves from its task's data. Every task's Frame
/// Generator answers with it (components/task: StateTableFrameGenerator); each only says what its
/// datums are (DatumSource). Core-free: KDL geometry only.

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/task/state_table.hpp"

namespace cobra::task {

/// Values per arm in a goal waypoint: x y z qx qy qz qw (m, unit quaternion), the encoding of the
/// motion components' multi-arm paths (cobra/components/motion/path_type.hpp).
inline constexpr std::size_t kPoseValues = 7;

/// Writes `pose` as x y z qx qy qz qw at `values[slot * kPoseValues]`. Allocates nothing.
void encodePose(const KDL::Frame& pose, std::size_t slot, std::vector<double>& values) noexcept;

/// "entry", "entry-0.02": the datum as the table writes it.
std::string describe(const Datum& datum);

/// Text of at most kCapacity characters held inline: a Frame Generator writes why it has no goal
/// in its real-time step, where nothing may allocate. Appending beyond the capacity keeps the
/// first kCapacity characters. Allocates nothing, throws nothing.
class FailureText {
 public:
  static constexpr std::size_t kCapacity = 511;
  void clear() noexcept { size_ = 0; }
  FailureText& operator<<(std::string_view text) noexcept;
  FailureText& operator<<(int value) noexcept;
  /// The datum as the table writes it (describe()).
  FailureText& operator<<(const Datum& datum) noexcept;
  std::string_view view() const noexcept { return {chars_.data(), size_}; }

 private:
  std::array<char, kCapacity> chars_{};
  std::size_t size_ = 0;
};

/// Where a row's datums come from: the Frame Generator reading the table.
class DatumSource {
 public:
  enum class Outcome {
    Resolved,
    Missing,    ///< its data has not arrived (no measured pose yet, no stitch planned ...)
    NotComing,  ///< a later task step that will not come (the needle after the last): a
                ///< room_for_* naming it is left out; elsewhere it is Missing
  };
  /// The pose (m, rad, task frame) `datum` names for `arm` before its offset, into `pose`; on
  /// Missing or NotComing, `why` says what is missing. Must allocate nothing when it resolves.
  virtual Outcome resolve(const Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) = 0;

 protected:
  ~DatumSource() = default;
};

/// A datum of the row its source could not give. Filling it allocates nothing.
struct GoalFailure {
  const char* key_prefix = "";  ///< with `arm`, the row's key: "" + "needle", "then_" + "probe" ...
  std::string_view arm;         ///< the arm's name (a view of the vocabulary's)
  const Datum* datum = nullptr;
  const char* why = "";
  /// Appends "needle=entry-0.02: no more needles" to `out`. Allocates nothing.
  void write(FailureText& out) const noexcept;
  /// The same text as a string (allocates: for tests and tools).
  std::string message() const;
};

/// The row of task state `state` in `table` (read from `table_file`); nullptr, with `failure`
/// set to "task state 'STATE' matches no row of FILE", when none matches. Allocates nothing.
const StateRow* rowFor(const StateTable& table, std::string_view state, std::string_view table_file,
                       FailureText& failure) noexcept;
/// Appends "task state 'STATE' (FILE:LINE): " to `out`: what a Frame Generator's failures for a
/// row start with. Allocates nothing.
void rowWhere(std::string_view state, std::string_view table_file, const StateRow& row, FailureText& out) noexcept;

/// Whether the row's goalPoses carries checks (several alternatives, then_*, room_for_*): without
/// them it is one waypoint, the goal pair (2 × kPoseValues values).
bool hasChecks(const StateRow& row) noexcept;

/// The goal pair of the row's first alternative into `first` (arm 0, arm 1), after checking that
/// every alternative's datums resolve. false with `failure` filled when one does not. Allocates
/// nothing for a row of one alternative whose datums resolve.
bool firstGoal(const StateRow& row, const std::array<std::string, 2>& arms, DatumSource& source,
               std::array<KDL::Frame, 2>& first, GoalFailure& failure);

/// The goal alternatives of a row: the waypoints of its goalPoses.
std::size_t goalAlternatives(const StateRow& row) noexcept;
/// The most values one waypoint of the row's goalPoses holds (every room_for_* coming).
std::size_t checkedGoalValues(const StateRow& row) noexcept;

/// goalPoses with checks (the MotionPlanner's): one waypoint per alternative, the preferred first:
/// [goal pair, where the straight motion after it goes (then_*; the goal again for an arm without
/// one), then per room_for_* that arm's later motion as its start pair and end pair with the
/// other arm at its goal; left out when the motion is NotComing]. `waypoints` holds exactly
/// goalAlternatives(row) entries; each is resized to its values. Allocates nothing when each has
/// the capacity of checkedGoalValues(row) (a Frame Generator reserves it at configure) and the
/// source resolves without allocating. false with `failure` filled when a datum does not resolve.
bool checkedGoals(const StateRow& row, const std::array<std::string, 2>& arms, DatumSource& source,
                  std::span<std::vector<double>> waypoints, GoalFailure& failure);

}  // namespace cobra::task
