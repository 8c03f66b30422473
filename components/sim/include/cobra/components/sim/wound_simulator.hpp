#pragma once
/// @file
/// The simulated patient of the suturing task (thesis ch. 5): a planar wound (sim::Wound) on which
/// the Endo Stitch applies stitches, the thread they pull, the stick that hooks it, and the wound's
/// edges as the sensing module would see them (§5.2.1), behind ports.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/bounded_string.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "cobra/sim/wound.hpp"

namespace cobra::components {

/// Bridge (it stands for the patient). Frames: world W; the wound frame at `wound_pose` (W_T_wound:
/// skin z = 0, +z out of the skin; sim/README.md). Needs a periodic activity.
///
/// Properties (SI): `cut` (x, y pairs of the cut's centreline in the wound frame, m, >= 2 pairs;
/// default a straight 40 mm cut along x), `wound_pose`, `max_gap` (m), `tissue_stiffness` (N/m),
/// `closure_spread` (m), `bite` (m), `stitch_depth` (m), `stitch_tolerance` (m), `closed_gap` (m),
/// `thread_length` (m), `thread_slack` (m), `thread_stiffness` (N/m), `breaking_tension` (N),
/// `hook_radius` (m), `release_time` (s, default 0.2: the thread's pull on the stick fades over it
/// once the stick lets go, instead of vanishing in one step), `edge_samples` (points per edge published on woundEdges, >= 2). Defaults:
/// sim::WoundModel / sim::ThreadModel.
///
/// Inputs: `toolTipPose` (KDL::Frame, m, W: the Endo Stitch's tip, moved by `tool_tip`, KDL::Frame,
/// m: the tip in the frame the port gives, e.g. a robot's tool frame; default identity),
/// `stickTipPose` (KDL::Frame, m, W: the tip of the stick held by the left arm's gripper, e.g. the
/// robot's left tool pose with its tool frame on the stick's tip); until both have arrived the
/// thread is not stepped.
/// `endoStitchActuations` (int, the robot's count of completed Endo Stitch actuations, from 0 at
/// its start): each increment applies a half-stitch at the tip's current pose, on the edge the
/// tip is at (sim::Wound::sideAt): the chart asks the robot to actuate the tool, the tool's
/// needle transfer is what the wound sees. A count lower than the last one (the robot restarted)
/// is taken as the new origin. `inputEvents` (event port): `release_event` ("e_release_thread")
/// makes the stick let the thread go.
/// Outputs: `toolWrench`, `stickWrench` (KDL::Wrench, N, N·m, world axes: the tensed thread's pull
/// on the tip, sim::Wound::toolForce / stickForce, about the origin of the frame `toolTipPose` /
/// `stickTipPose` gives — the robot's tool point —, so the torque is the tip's lever arm (`tool_tip`,
/// in world axes) × the force; `stickTipPose` is the stick's tip itself (the left tool frame), so
/// `stickWrench` has no torque; a robot's contact wrench inputs, whose reference point is that
/// tool point);
/// `events`: e_stitch_applied, e_stitch_missed (why: `missReason`, the sim::StitchMiss
/// code, and `missDistance`, m), e_thread_hooked, e_thread_broken; `threadTension` (N), `stitchCount` (complete stitches), `maxStitchGap`
/// (m, the largest gap at a stitch, 0 with none), `woundEdges` (vector<double>: for each of
/// `edge_samples` places along the cut, the right then the left edge point on the skin, x y z in W,
/// m: the sensing module's stand-in, §5.2.1), `maxGap` (m, the widest gap along the cut),
/// `threadPath` (vector<double>: the thread's path as sim::Wound computes its length, x y z in W,
/// m: the skin points of the half-stitches in order, the point where it bends round the stick
/// while hooked, then the Endo Stitch's tip unless broken; empty before the first stitch),
/// `stitchLines` (vector<double>: the thread inside the tissue, segments of two points (6 numbers),
/// x y z in W, m: per half-stitch its skin point to its edge point at stitch_depth, per complete
/// stitch also the crossing from the right edge point to the left one), all
/// written every step; the gap-dependent ones are recomputed only when the wound's revision
/// changed (sim::Wound::revision).
/// updateHook allocates nothing once its connections' slots have the edges' size: those made after
/// configure from the start (the edge buffer is sized there, setDataSample), one made before by its
/// first writes.
class WoundSimulator : public core::Component {
 public:
  explicit WoundSimulator(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  void actuate() noexcept;
  /// Writes the outputs, recomputing the gap-dependent ones when the wound's revision changed (or `all`).
  void publish(bool all) noexcept;
  /// Writes threadPath and stitchLines (they follow the tools: every step).
  void publishThread() noexcept;

  core::Property<std::vector<double>> cut_{"cut", {-0.02, 0.0, 0.02, 0.0}, "m",
                                           "x, y pairs of the cut's centreline in the wound frame"};
  core::Property<KDL::Frame> wound_pose_{"wound_pose", KDL::Frame::Identity(), "m",
                                         "wound frame (skin z = 0, +z out of the skin) in the world"};
  core::Property<double> max_gap_{"max_gap", sim::WoundModel{}.max_gap, "m", "the edges' distance at the middle"};
  core::Property<double> tissue_stiffness_{"tissue_stiffness", sim::WoundModel{}.tissue_stiffness, "N/m",
                                           "thread tension per metre a stitch closes"};
  core::Property<double> closure_spread_{"closure_spread", sim::WoundModel{}.closure_spread, "m",
                                         "half-width over which a stitch narrows the gap"};
  core::Property<double> bite_{"bite", sim::WoundModel{}.bite, "m", "the thread's skin point beyond the edge"};
  core::Property<double> stitch_depth_{"stitch_depth", sim::WoundModel{}.stitch_depth, "m",
                                       "depth of the edge point the tip must reach"};
  core::Property<double> stitch_tolerance_{"stitch_tolerance", sim::WoundModel{}.stitch_tolerance, "m",
                                           "how close the tip must be to the edge point"};
  core::Property<double> closed_gap_{"closed_gap", sim::WoundModel{}.closed_gap, "m",
                                     "a stitch's gap below this counts as closed"};
  core::Property<double> thread_length_{"thread_length", sim::ThreadModel{}.length, "m", "the whole thread"};
  core::Property<double> thread_slack_{"thread_slack", sim::ThreadModel{}.slack, "m",
                                       "loop left after each half-stitch"};
  core::Property<double> thread_stiffness_{"thread_stiffness", sim::ThreadModel{}.stiffness, "N/m",
                                           "tension per metre stretched"};
  core::Property<double> breaking_tension_{"breaking_tension", sim::ThreadModel{}.breaking_tension, "N",
                                           "the thread breaks above it"};
  core::Property<double> hook_radius_{"hook_radius", sim::ThreadModel{}.hook_radius, "m",
                                      "the stick catches the thread within this distance"};
  // ASSUMPTION: the gripper turns the stick's tip out of the thread in 0.2 s (sim::ThreadModel::release_time).
  core::Property<double> release_time_{"release_time", 0.2, "s",
                                       "the thread slides off the stick over this time once it lets go, >= 0"};
  core::Property<KDL::Frame> tool_tip_offset_{"tool_tip", KDL::Frame::Identity(), "m",
                                              "the Endo Stitch's tip in the frame toolTipPose gives"};
  core::Property<int> edge_samples_{"edge_samples", 41, "1", "points per edge on woundEdges, >= 2"};
  core::Property<std::string> release_event_{"release_event", "e_release_thread", "", "the stick lets the thread go"};

  core::InputPort<KDL::Frame> tool_tip_{"toolTipPose", "the Endo Stitch's tip, world frame", "m"};
  core::InputPort<KDL::Frame> stick_tip_{"stickTipPose", "the stick's tip, world frame", "m"};
  core::InputPort<int> actuations_{"endoStitchActuations", "the robot's count of completed Endo Stitch actuations", "1"};
  core::InputPort<core::Event> input_events_{"inputEvents", "thread release requests", ""};
  core::OutputPort<double> tension_{"threadTension", "thread tension", "N"};
  core::OutputPort<KDL::Wrench> tool_wrench_{"toolWrench", "the thread's pull on the Endo Stitch's tip, world, about the toolTipPose frame's origin", "N, N·m"};
  core::OutputPort<KDL::Wrench> stick_wrench_{"stickWrench", "the hooked thread's pull on the stick's tip, world, about the stickTipPose frame's origin", "N, N·m"};
  core::OutputPort<int> stitch_count_{"stitchCount", "complete stitches", "1"};
  core::OutputPort<double> max_stitch_gap_{"maxStitchGap", "largest gap at a stitch (0 with none)", "m"};
  core::OutputPort<double> max_gap_out_{"maxGap", "the widest gap along the cut", "m"};
  core::OutputPort<int> miss_reason_{"missReason", "why the last actuation applied no stitch (sim::StitchMiss)", "1"};
  core::OutputPort<double> miss_distance_{"missDistance", "tip to the edge point at the last miss", "m"};
  core::OutputPort<std::vector<double>> edges_{
      "woundEdges", "right then left edge point (x y z) at each sample along the cut, world frame", "m"};
  core::OutputPort<std::vector<double>> thread_path_{
      "threadPath", "the thread's path (x y z per point): skin points in order, the stick's bend, the tip; world", "m"};
  core::OutputPort<std::vector<double>> stitch_lines_{
      "stitchLines", "the thread in the tissue: segments (two x y z points each), skin point to edge point; world", "m"};

  std::optional<sim::Wound> wound_;
  KDL::Frame world_to_wound_;
  KDL::Vector tool_, stick_;  // wound frame
  // m, world axes: the Endo Stitch's tip from the origin of the frame toolTipPose gives (the tip
  // offset rotated into the world): toolWrench's lever arm.
  KDL::Vector tool_lever_ = KDL::Vector::Zero();
  bool have_tool_ = false, have_stick_ = false;
  bool hooked_ = false, broken_ = false;
  int actuations_seen_ = 0;
  std::int64_t last_update_ns_ = -1;  // clock time of the last update; -1: none since start
  std::uint64_t published_revision_ = 0;
  int complete_ = 0;                 // of the published revision: complete stitches,
  double widest_stitch_gap_ = 0.0;   // m: the widest gap at a stitch,
  double widest_gap_ = 0.0;          // m: the widest gap along the cut
  core::BoundedString<63> release_name_;
  std::vector<double> edge_buffer_;
  // Sized at configure for the wound's max_stitches (resized within that capacity: no allocation).
  std::vector<double> thread_buffer_, stitch_buffer_;
};

}  // namespace cobra::components
