#pragma once
/// @file
/// The state table of a Frame Generator (thesis §4.5.5, §5.5): for each task state, the goal
/// datum of each of a task's two arms, with the checks the motion planner verifies the goal with.
/// The table serves any two-arm task: a TableVocabulary gives its arms' names (the keys of a row:
/// `needle=`, `then_needle=` ...) and the datums the task's Frame Generator resolves from its own
/// data; `hold` (the arm's measured pose) and the table's own `pose`s are common to every table.
/// Format (one statement per line, task/statements.hpp):
///
///     pose NAME xyz=X,Y,Z [rpy=R,P,Y]                  a fixed task-frame pose (m, rad)
///     state PATH A0=DATUM[|DATUM...] A1=DATUM[|DATUM...] [then_A0=DATUM] [then_A1=DATUM]
///           [room_for_A0=DATUM..DATUM] [room_for_A1=DATUM..DATUM]
///
/// A DATUM is NAME, NAME+M or NAME-M: the named pose moved M m along its own z axis (the tool's
/// axis: > 0 deeper). Core-free: KDL geometry only. Units: m, rad.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

namespace cobra::task {

/// What a row asks for one arm: a named datum moved `offset` m along the tool's z axis.
struct Datum {
  std::string name;  ///< a datum of the vocabulary, `hold`, or a table `pose`
  double offset = 0.0;
};

/// A straight motion of one arm from one datum to another (`room_for_*=FROM..TO`).
struct DatumMotion {
  Datum from, to;  ///< empty names: none
};

/// A row: when the task state's path contains `state` (dot-separated components, e.g.
/// "MoveToSkin.Approach"), the goal pair is goal(0), goal(1). Arm 0 is the vocabulary's first arm.
struct StateRow {
  std::string state;
  /// The goal datums of each arm (at least one). Several on one arm (`needle=a|b|c`) are
  /// alternatives, the preferred first: the motion planner takes the first that passes its checks
  /// (the goal, then_*, room_for_*) and to which it finds a path. At most one arm lists several.
  std::array<std::vector<Datum>, 2> goals;
  /// `then_A=`: where the straight motion that follows this goal (a motion primitive of the next
  /// task state) takes that arm; the goal is then published with it, and the motion planner
  /// verifies it with the path. Empty name: none.
  std::array<Datum, 2> thens;
  /// `room_for_A=F..T`: a straight motion that arm makes later, from F to T, while the other arm
  /// stays at this goal: the planner verifies every goal alternative with it.
  std::array<DatumMotion, 2> rooms;
  int line = 0;

  std::vector<Datum>& goal(std::size_t arm) noexcept { return goals[arm]; }
  const std::vector<Datum>& goal(std::size_t arm) const noexcept { return goals[arm]; }
  Datum& then(std::size_t arm) noexcept { return thens[arm]; }
  const Datum& then(std::size_t arm) const noexcept { return thens[arm]; }
  DatumMotion& roomFor(std::size_t arm) noexcept { return rooms[arm]; }
  const DatumMotion& roomFor(std::size_t arm) const noexcept { return rooms[arm]; }
};

/// The words of one task's state table: its two arms' names and the datums its Frame Generator
/// resolves from the task's data (besides `hold` and the table's own poses, which every table has).
struct TableVocabulary {
  std::array<std::string, 2> arms;
  std::vector<std::string> datums;
};

/// A parsed table: its rows and its fixed task-frame poses.
struct StateTable {
  std::vector<StateRow> rows;
  std::vector<std::pair<std::string, KDL::Frame>> poses;  ///< name -> pose in the task frame (m, rad)

  /// The row for task state `path` ("root.InsertingNeedles.MoveToSkin.Approach.AskingGoal"):
  /// among rows whose components appear contiguously in the path, the one ending deepest, then
  /// the longest. nullptr when none matches. Allocates nothing.
  const StateRow* find(std::string_view path) const;
  const KDL::Frame* pose(std::string_view name) const;
};

/// Parses a table with `vocabulary`'s words. `source` names the text in errors.
/// @throws std::invalid_argument "SOURCE:LINE: message" on syntax errors, unknown statements,
///         keys or datums, a state given twice, alternatives on both arms.
StateTable parseStateTable(std::string_view text, std::string_view source, const TableVocabulary& vocabulary);

/// True when the dot-separated components of `state` appear contiguously in `path`
/// ("MoveToSkin.Descend" in "root.InsertingNeedles.MoveToSkin.Descend.Moving"). Allocates nothing.
bool pathContains(std::string_view path, std::string_view state);

/// `pose` moved `offset` m along its own z axis.
KDL::Frame alongZ(const KDL::Frame& pose, double offset);

}  // namespace cobra::task
