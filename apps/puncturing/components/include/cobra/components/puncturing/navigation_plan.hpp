#pragma once
/// @file
/// The plan and registration a navigation peer sends over OpenIGTLink (apps/puncturing/README.md,
/// "Navigated puncturing"), made into the puncturing plan the Frame Generators and the motion
/// planners use in `plan_source = "navigation"`: the needles from a POINT list, their probe poses
/// by probePlan() (lib/probe_plan.hpp), the whole checked by validate(), and the registration
/// checked against the one the rest of the deployment was set up with. Both components build it
/// with this one function from the same messages, so that they hold the same plan.

#include <string>

#include <kdl/frames.hpp>

#include "cobra/core/port.hpp"
#include "cobra/puncturing/plan.hpp"
#include "cobra/types/point_list.hpp"

namespace cobra::components::puncturing_navigation {

/// m: how far the navigation's registration of frame A may lie from the preoperative `abdomen`
/// (the pose the planning scene's phantom, the monitors' forbidden regions and the simulated
/// patient are placed with at configure) for the controllers to take it. Beyond it the planner's
/// phantom and the monitors would be somewhere else than where the plan's goals are: refused.
inline constexpr double kRegistrationTolerance = 0.002;
/// rad: the same for the rotation (about 1 deg).
inline constexpr double kRegistrationAngleTolerance = 0.0175;

/// Where a navigated plan's errors point: "POINT 'Plan':K" (K the needle's first point, 1-based).
inline constexpr const char* kPlanSource = "navigation plan";

/// What a component reads from the navigation until it takes the plan: the plan's points (the
/// latest list) and the registration (the latest). Fixed size: reading allocates nothing.
struct NavigationInputs {
  types::PointList points;
  KDL::Frame registration = KDL::Frame::Identity();
  bool have_points = false, have_registration = false;

  /// Reads both ports (a real-time step may); true once both have come.
  bool read(core::InputPort<types::PointList>& plan, core::InputPort<KDL::Frame>& abdomen) {
    if (abdomen.read(registration) != core::FlowStatus::NoData) have_registration = true;
    if (plan.readNew(points) == core::FlowStatus::NewData) have_points = true;
    return have_points && have_registration;
  }
  /// What has not come: "no plan (POINT) and no registration (TRANSFORM)", "no plan (POINT)",
  /// "no registration (TRANSFORM)", or "" when both have.
  const char* missing() const {
    return !have_points && !have_registration ? "no plan (POINT) and no registration (TRANSFORM)"
           : !have_points                     ? "no plan (POINT)"
           : !have_registration               ? "no registration (TRANSFORM)"
                                              : "";
  }
};

/// Builds `plan` from the navigation's points (frame A, m: `<needle>.entry` and
/// `<needle>.target`, the needles in the order their first point comes, roll 0), the registered
/// pose of A in the world (`registration`, m) and the preoperative information (tumour, forbidden
/// regions, entry disc; its `abdomen` the pose the deployment was set up with). Returns "" when
/// the plan is taken (plan.preoperative.abdomen_in_task = registration), else the refusal, one
/// line: a point named otherwise, a needle without its entry or target, no needle, more points than
/// one list holds, what validate() refuses ("navigation plan:K: needle 'n2': target is 30.0 mm from
/// the tumour centre, outside its radius 12.0 mm"), or a registration too far from the
/// preoperative one. Allocates (once per plan; not a real-time step's work).
std::string buildPlan(const types::PointList& points, const KDL::Frame& registration,
                      const puncturing::PreoperativeInfo& preoperative, puncturing::PuncturingPlan& plan);

/// "registration (x, y, z mm; roll, pitch, yaw deg), plan of N needles: n1 entry (x, y, z mm) target (...), ..."
std::string describe(const puncturing::PuncturingPlan& plan);

}  // namespace cobra::components::puncturing_navigation
