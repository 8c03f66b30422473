#pragma once
/// @file
/// A whole procedure verified before its first motion: the motion states two task charts will
/// run, in their order, each with the goal its state table row gives, each arm starting where the
/// previous step left it. The walker resolves each row's datums (the task's items through an
/// ItemDatumSource, `hold` from where the walk left that arm, the table's own poses) and asks a
/// StepVerifier (a motion planner: task/planned_walk.hpp) whether the step can be made; the first
/// step that cannot is the procedure's refusal, naming the item, the state, the datum and why.
/// Core-free and planner-free: KDL geometry only. Units: m, rad.

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/task/goals.hpp"
#include "cobra/task/state_table.hpp"

namespace cobra::task {

/// One motion state of a chart, in the order the charts visit them.
struct ProcedureStep {
  std::string state;     ///< the task state path whose row gives the goal ("root.MoveToSkin.Approach")
  std::size_t arm = 0;   ///< the arm whose chart makes the motion (the other holds its pose)
  bool planned = false;  ///< a planned path (the chart's Planning step) or a straight motion primitive
  std::size_t item = 0;  ///< the task item (needle, stitch) current in that arm's chart, 0-based
};

/// A task's datums for one of its items (a needle, a stitch), besides `hold` and the table's
/// poses, which the walker resolves itself.
class ItemDatumSource : public DatumSource {
 public:
  /// Makes `item` the current one: what "entry", "next_probe" ... refer to from now on.
  virtual void select(std::size_t item) = 0;
  /// The item's name for messages ("needle n2").
  virtual std::string itemName(std::size_t item) const = 0;

 protected:
  ~ItemDatumSource() = default;
};

/// A pair of tool poses: arm 0, arm 1 (m, rad, task frame).
using PosePair = std::array<KDL::Frame, 2>;

/// One goal alternative of a row with what it is verified with (the MotionPlanner's goalPoses
/// waypoint, decoded).
struct GoalCandidate {
  PosePair goal;
  PosePair then;           ///< where the straight motion after the goal goes (the goal: none)
  bool has_then = false;
  std::vector<std::pair<PosePair, PosePair>> rooms;  ///< later straight motions to leave room for
  std::string datum;       ///< the moving arm's datum as the table writes it ("needle_change")
};

/// What a StepVerifier says of a step.
struct StepOutcome {
  bool ok = false;
  std::size_t chosen = 0;  ///< the alternative taken (ok)
  PosePair reached;        ///< where the tools are after the step (ok)
  std::string why;         ///< why not (not ok): the verifier's reason
};

/// Verifies one step from where the previous one left the robots (the verifier keeps that state,
/// e.g. the joints, and moves it on when a step passes).
class StepVerifier {
 public:
  /// A planned step: the first candidate that passes its checks and to which a path is found.
  virtual StepOutcome planned(const ProcedureStep& step, std::span<const GoalCandidate> candidates) = 0;
  /// A motion primitive: the straight motion from `from` to `to` (the scene's primitive
  /// contacts allowed).
  virtual StepOutcome straight(const ProcedureStep& step, const PosePair& from, const PosePair& to) = 0;

 protected:
  ~StepVerifier() = default;
};

/// Why a procedure cannot be made: the first step that fails.
struct Refusal {
  std::size_t step = 0;  ///< index into the walked steps
  std::string item;      ///< "needle n2"
  std::string state;     ///< the step's task state
  int line = 0;          ///< its row's line in the table (0: no row)
  std::string datum;     ///< "needle=entry-0.02": the moving arm's goal datum(s)
  std::string why;
  /// "needle n2, task state 'root...Approach' (FILE:LINE), needle=entry-0.02: WHY"
  std::string text(std::string_view table_file) const;
};

/// The outcome of a walk.
struct ProcedureVerdict {
  bool ok = false;
  std::vector<std::size_t> chosen;  ///< per step: the goal alternative taken (the preferred: 0)
  Refusal refusal;                  ///< !ok
};

/// Walks `steps` from the tools at `start`: each step's row (`table`, read from `table_file`) gives
/// its goal (the arm that does not move holds), resolved for the step's item; a planned step is
/// given the row's goal alternatives with their then_* and room_for_* checks, a motion primitive
/// the straight motion from where the moving arm is to its goal. Stops at the first step the
/// verifier refuses, or whose datums do not resolve, or that has no row.
ProcedureVerdict walkProcedure(const StateTable& table, std::string_view table_file,
                               const std::array<std::string, 2>& arms, std::span<const ProcedureStep> steps,
                               const PosePair& start, ItemDatumSource& source, StepVerifier& verifier);

/// The candidates of one goalPoses waypoint set (checkedGoals' encoding; a waypoint of 14 values
/// is a goal pair without checks). `datums` names each alternative.
std::vector<GoalCandidate> decodeCandidates(std::span<const std::vector<double>> waypoints,
                                            const std::vector<std::string>& datums);

}  // namespace cobra::task
