#pragma once
/// @file
/// The stitch planning component of the suturing task (thesis §5.2.1, the chart's
/// WaitStitchesPlan / GetStitchTargetPose): the next stitch's two targets from the wound's edges
/// as the sensing module publishes them now (cobra::suturing::StitchPlanner).

#include <string>

#include <kdl/frames.hpp>

#include "cobra/core/component.hpp"
#include "cobra/core/request.hpp"
#include "cobra/suturing/stitch_plan.hpp"

namespace cobra::components {

/// Calculation component. Interface (SI):
/// - properties `spacing`, `end_margin`, `depth`, `closed_gap` (m: suturing::StitchPlanModel),
///   `max_edge_samples` (points per edge the input may carry, storage reserved at configure);
/// - input `woundEdges` (vector<double>, m, world: for each place along the cut the right then
///   the left edge point, x y z; WoundSimulator's output or a real sensing module's);
///   `skin_normal` property (KDL::Vector, unit, world: out of the skin);
/// - outputs `rightStitchPose`, `leftStitchPose` (KDL::Frame, m, world: where the Endo Stitch's
///   tip applies each half; x along the cut, z out of the skin, y from the right edge to the
///   left), `stitchIndex` (int, 0-based place in the plan), `stitchGap` (m, the edges' distance
///   there when planned), `plannedStitches` (int: how many the cut takes);
/// - operations `askStitch()`: plan the current stitch (the first open place at or after the
///   current index) from the newest edges, answered in this component's next step with
///   `e_stitch_planned` (outputs written), `e_stitches_done` (none left) or `e_no_wound_data`
///   (no edges yet, or edges that are not two facing polylines); `nextStitch()`: the current
///   index moves past the last planned stitch; `restartPlan()`: back to stitch 0.
/// Real time: the answer allocates nothing for edges up to `max_edge_samples` points.
class StitchPlannerComponent : public core::Component {
 public:
  explicit StitchPlannerComponent(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  void answer() noexcept;

  core::Property<double> spacing_{"spacing", suturing::StitchPlanModel{}.spacing, "m", "between stitches along the cut"};
  core::Property<double> end_margin_{"end_margin", suturing::StitchPlanModel{}.end_margin, "m",
                                     "first and last stitch from the cut's ends"};
  core::Property<double> depth_{"depth", suturing::StitchPlanModel{}.depth, "m", "the targets' depth below the skin"};
  core::Property<double> closed_gap_{"closed_gap", suturing::StitchPlanModel{}.closed_gap, "m",
                                     "a place with a smaller gap needs no stitch"};
  core::Property<KDL::Vector> skin_normal_{"skin_normal", KDL::Vector(0.0, 0.0, 1.0), "1",
                                           "unit vector out of the skin, world frame"};
  core::Property<int> max_edge_samples_{"max_edge_samples", 1024, "1", "points per edge the input may carry"};

  core::InputPort<std::vector<double>> edges_in_{"woundEdges", "right then left edge point (x y z) per place, world",
                                                  "m"};
  core::OutputPort<KDL::Frame> right_{"rightStitchPose", "the right half-stitch's target, world", "m"};
  core::OutputPort<KDL::Frame> left_{"leftStitchPose", "the left half-stitch's target, world", "m"};
  core::OutputPort<int> index_{"stitchIndex", "the planned stitch's place in the plan, 0-based", "1"};
  core::OutputPort<double> gap_{"stitchGap", "the edges' distance at the planned stitch", "m"};
  core::OutputPort<int> planned_{"plannedStitches", "stitches the cut takes", "1"};

  suturing::StitchPlanner planner_;
  suturing::WoundEdges edges_;
  std::vector<double> samples_;
  core::PendingRequest ask_, next_, restart_;
  int current_ = 0;       // the first place askStitch may plan
  int last_planned_ = -1;
};

}  // namespace cobra::components
