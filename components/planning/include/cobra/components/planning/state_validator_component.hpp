#pragma once
/// @file
/// The thesis' State Validator (§5.4.2): a Calculation component between the teleoperation
/// coupling and the robot driver that passes a pair of set-points on only when isStateValid
/// accepts it (reachable and collision-free), and holds the last valid pair otherwise.

#include <memory>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/components/planning/planning_scene_component.hpp"

namespace cobra::components {

/// Interface (scene properties: PlanningSceneComponent):
/// - ports in: `desPoseIn_1`, `desPoseIn_2` (KDL.Frame, world, m: the set-points of tool 1 and
///   tool 2 of the scene, e.g. the Endo Stitch and the gripper; both event ports);
///   out: `desPoseOut_1`, `desPoseOut_2` (KDL.Frame, m: the last valid pair), `heldPose_1`,
///   `heldPose_2` (KDL.Frame, m: in each step that rejects a pair after a valid one, the valid pair
///   the robot is held at, for the producers of the set-points to re-sync to, e.g. the variable
///   admittances' heldPose: ARCHITECTURE §7), `minDistance`
///   (double, m: minimum distance of the checked pair of the incoming set-points; NaN when
///   unreachable or not a pose);
/// - operations `lastReason()` (why the last rejected pair was rejected);
/// - events `e_state_invalid` (first rejected pair after valid ones), `e_state_valid` (first
///   valid pair after rejected ones).
/// Before the first valid pair nothing is written. A pair is checked when either input has new
/// data, with the other input's latest value.
///
/// Real time: on a scene of primitives only (the shipped scenes) updateHook allocates nothing and
/// does not block: IK/FK of the robot models, FCL object updates and distance queries with FCL's
/// own GJK (FCL's default, libccd, allocates per query: cobra does not use it), port writes and
/// events (test: StateValidatorComponent.UpdateAllocatesNothing). Its time is that of one check,
/// ~20-25 µs of CPU for a valid puncturing state (bench/planning_bench.cpp), so it runs at
/// teleoperation rates (1 kHz) in a periodic activity. With CAD meshes (mesh name properties) the
/// BVH distance of FCL is not proven allocation-free.
class StateValidatorComponent : public PlanningSceneComponent {
 public:
  explicit StateValidatorComponent(std::string name);
  ~StateValidatorComponent() override;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  core::InputPort<KDL::Frame> in_1_{"desPoseIn_1", "set-point of tool 1 to check, world", "m"};
  core::InputPort<KDL::Frame> in_2_{"desPoseIn_2", "set-point of tool 2 to check, world", "m"};
  core::OutputPort<KDL::Frame> out_1_{"desPoseOut_1", "last valid set-point of tool 1, world", "m"};
  core::OutputPort<KDL::Frame> out_2_{"desPoseOut_2", "last valid set-point of tool 2, world", "m"};
  core::OutputPort<KDL::Frame> held_1_{"heldPose_1",
                                      "in each step rejecting a pair: the held set-point of tool 1, world", "m"};
  core::OutputPort<KDL::Frame> held_2_{"heldPose_2",
                                      "in each step rejecting a pair: the held set-point of tool 2, world", "m"};
  core::OutputPort<double> min_distance_{"minDistance", "minimum distance of the incoming set-points", "m"};

  std::unique_ptr<planning::StateValidator> validator_;
  planning::DualPose incoming_;
  planning::DualPose last_valid_;
  bool have_1_ = false;
  bool have_2_ = false;
  bool have_valid_ = false;
  bool was_valid_ = true;
  planning::ValidityResult last_rejected_;  // names point into the validator's scene
};

}  // namespace cobra::components
