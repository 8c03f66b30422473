#pragma once
/// @file
/// The state table's evaluator (thesis §4.5.5): a row's goal pair and its goal alternatives with
/// their checks, from datums a Frame Generator resolves from its task's data. Every task's Frame
/// Generator answers with it (components/task: StateTableFrameGenerator); each only says what its
/// datums are (DatumSource). Core-free: KDL geometry only.

#include <array>
#include <cstddef>
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

/// A datum of the row its source could not give.
struct GoalFailure {
  std::string key;              ///< the row's key: "needle", "then_probe", "room_for_needle" ...
  const Datum* datum = nullptr;
  const char* why = "";
  /// "needle=entry-0.02: no more needles".
  std::string message() const;
};

/// The row of task state `state` in `table` (read from `table_file`); nullptr, with `failure` =
/// "task state 'STATE' matches no row of FILE", when none matches. Allocates nothing when one does.
const StateRow* rowFor(const StateTable& table, std::string_view state, std::string_view table_file,
                       std::string& failure);
/// "task state 'STATE' (FILE:LINE): ": what a Frame Generator's failures for a row start with.
std::string rowWhere(std::string_view state, std::string_view table_file, const StateRow& row);

/// Whether the row's goalPoses carries checks (several alternatives, then_*, room_for_*): without
/// them it is one waypoint, the goal pair (2 × kPoseValues values).
bool hasChecks(const StateRow& row) noexcept;

/// The goal pair of the row's first alternative into `first` (arm 0, arm 1), after checking that
/// every alternative's datums resolve. false with `failure` filled when one does not. Allocates
/// nothing for a row of one alternative whose datums resolve.
bool firstGoal(const StateRow& row, const std::array<std::string, 2>& arms, DatumSource& source,
               std::array<KDL::Frame, 2>& first, GoalFailure& failure);

/// goalPoses with checks (the MotionPlanner's): one waypoint per alternative, the preferred first:
/// [goal pair, where the straight motion after it goes (then_*; the goal again for an arm without
/// one), then per room_for_* that arm's later motion as its start pair and end pair with the
/// other arm at its goal; left out when the motion is NotComing]. false with `failure` filled
/// when a datum does not resolve.
bool checkedGoals(const StateRow& row, const std::array<std::string, 2>& arms, DatumSource& source,
                  std::vector<std::vector<double>>& waypoints, GoalFailure& failure);

}  // namespace cobra::task
