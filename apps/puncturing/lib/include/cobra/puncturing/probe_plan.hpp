#pragma once
/// @file
/// The ultrasound probe plan computed from the cryoablation plan (thesis §4.2.2: the offline US
/// probe planner, in its simplest form), so that a needle plan received at run time (from the
/// navigation software) needs no us_plan.txt. The poses are those apps/puncturing/tools/probe_plan.py
/// writes into us_plan.txt (the test cross-checks the shipped plans and the script itself): the
/// probe face on the skin in the vertical plane that contains the needle, 45 mm beyond where the
/// needle's tip lies seen from above, its beam (z) pointing at the needle's target, its array (x)
/// in that plane, away from the needle. Core-free: KDL geometry only. Frame A, m, rad.

#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/puncturing/plan.hpp"

namespace cobra::puncturing {

/// m: the probe face's centre beyond the needle tip's horizontal offset from the entry. Nearer,
/// the UR5 holding the probe comes within 5 mm of the I-SUR's micro arm at the needle's target in
/// registrations turned by tens of degrees (apps/puncturing/README.md, "Setups vary").
inline constexpr double kProbeBeyondTip = 0.045;
/// m: a vertical needle leaves no vertical plane to choose: the imaging plane is A's y-z plane and
/// the face lies this far along -y from the entry, on the UR5's side (along +x the probe would
/// meet the I-SUR's forearm above the needle), as the vertical_needle scenario's us_plan.txt
/// places it. (probe_plan.py divides by zero there.)
inline constexpr double kProbeBesideVerticalNeedle = 0.035;

/// The probe pose for one needle, frame A (z along the beam, x along the array; the imaging plane
/// x-z contains the needle). A needle is vertical when the sine of its tilt is below 1e-12.
KDL::Frame probePose(const PlannedNeedle& needle);

/// One probe pose per needle, in the needles' order, each named after its needle and carrying its
/// needle's line; then the whole plan is checked against the preoperative information
/// (validate(), plan.hpp), so that a probe that could not see its needle is refused here rather
/// than when the plan is loaded. `cryo_source` names the needles' text in errors.
/// @throws std::invalid_argument "CRYO_SOURCE:LINE: needle 'N': ..." or "...: probe for 'N': ...".
std::vector<PlannedProbe> probePlan(const std::vector<PlannedNeedle>& needles, const PreoperativeInfo& preoperative,
                                    std::string_view cryo_source = "cryo plan");

}  // namespace cobra::puncturing
