#pragma once
/// @file
/// The suturing task's Frame Generator (thesis §5.5, after the puncturing one of §4.5.5): the goal
/// poses of both arms for the current task state, from a state table whose datums are the current
/// stitch (the StitchPlanner's targets, input ports) and the arms' measured poses: the framework's
/// StateTableFrameGenerator (components/task) with the suturing task's datums.

#include <array>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/components/task/state_table_frame_generator.hpp"

namespace cobra::components {

/// Bridge. Arms: `right` (arm 0, the Endo Stitch's tip) and `left` (arm 1, the stick's tip).
///
/// Datums (state table, `state PATH right=DATUM left=DATUM`): each a tool pose whose z axis points
/// into the skin and x along the cut (so that NAME+M is M m deeper, NAME-M M m out of the skin, as in
/// the puncturing table): `right_edge` / `left_edge` = the current stitch's right / left target
/// (the StitchPlanner's rightStitchPose / leftStitchPose: the edge point at the stitch depth);
/// `centre` = their midpoint (inside the wound); `pull` (the Endo Stitch pulling the thread) =
/// `centre` moved by `pull_offset` (m, stitch frame: x along the cut, y from the right edge to the
/// left, z out of the skin); `aside` (where the stick waits out of the Endo Stitch's way while it
/// stitches: the same place for both halves) = `centre` moved by `aside_offset` (stitch frame, so
/// +y is the left edge's side, the stick's own); `hook` (the stick through the free thread), `push`
/// (the stick having pushed the thread back along the cut) = the edge target of the last
/// half-stitch moved by `hook_offset`, `push_offset`
/// (m, in that half's frame: x along the cut, y outward from the wound on that side, z out of the
/// skin): the free thread leaves the skin beyond the edge of the last half. The last half is the
/// one of the last task state answered whose path contains `right_half_state` or
/// `left_half_state` (default ApplyRightStitch, ApplyLeftStitch; the right one before any);
/// `hold` = the arm's measured pose; a table `pose` = a fixed world pose.
///
/// Each arm is commanded in its tool's datum frame (the robot's tool frame is the tip: the
/// application gives it once, apps/suturing/frames.lua): a goal is the datum pose itself, `hold`
/// the measured pose.
///
/// Interface (besides StateTableFrameGenerator's: `state_table_file`, `currentTaskState`,
/// `desiredPoses`, `goalPoses` (right then left), `askCurrentGoal()`, `lastFailure()`; measured on
/// `rightMeasPose` and `leftMeasPose`):
/// - properties: the four offsets above, `right_half_state`, `left_half_state`;
/// - inputs `rightStitchPose`, `leftStitchPose` (KDL.Frame, m, world: x along the cut, z out of
///   the skin).
/// Real time: as StateTableFrameGenerator's.
class SuturingFrameGenerator : public StateTableFrameGenerator {
 public:
  explicit SuturingFrameGenerator(std::string name);

  /// The table's words: arms right and left, the datums above.
  static const task::TableVocabulary& suturingVocabulary();

 protected:
  bool startHook() override;
  void readTaskInputs() override;
  void taskStateRead(std::string_view path) override;
  Outcome resolveTaskDatum(const task::Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) override;

 private:
  core::Property<KDL::Vector> pull_offset_{"pull_offset", KDL::Vector(0.0, 0.0, 0.037), "m",
                                           "the Endo Stitch pulling the thread, from the stitch's centre (stitch frame)"};
  // The default: the suturing application's (apps/suturing/deployment/controller.lua, where it is
  // argued), off the free thread's line and out of the Endo Stitch's way on the I-SUR.
  core::Property<KDL::Vector> aside_offset_{"aside_offset", KDL::Vector(-0.016, 0.018, 0.015), "m",
                                            "the stick waiting out of the Endo Stitch's way, from the stitch's centre "
                                            "(stitch frame: +y towards the left edge)"};
  // The thread datums' defaults, for the sim::Wound defaults (4 mm bite, the pull 37 mm above the
  // stitch's centre): 18 mm above the skin the free thread is about 0.4 mm outward of the edge.
  core::Property<KDL::Vector> hook_offset_{"hook_offset", KDL::Vector(0.0, 0.0005, 0.02), "m",
                                           "the stick through the free thread, from the last half's edge target"};
  core::Property<KDL::Vector> push_offset_{"push_offset", KDL::Vector(-0.006, 0.0005, 0.02), "m",
                                           "the stick having pushed the thread aside, from the last half's edge target"};
  core::Property<std::string> right_half_state_{"right_half_state", "ApplyRightStitch", "",
                                                "task state path component of the right half-stitch"};
  core::Property<std::string> left_half_state_{"left_half_state", "ApplyLeftStitch", "",
                                               "task state path component of the left half-stitch"};

  core::InputPort<KDL::Frame> right_stitch_{"rightStitchPose", "the current stitch's right target, world", "m"};
  core::InputPort<KDL::Frame> left_stitch_{"leftStitchPose", "the current stitch's left target, world", "m"};

  std::array<KDL::Frame, 2> stitch_;  // right, left target
  std::array<bool, 2> have_stitch_{false, false};
  std::size_t last_half_ = 0;  // 0: right, 1: left
};

}  // namespace cobra::components
