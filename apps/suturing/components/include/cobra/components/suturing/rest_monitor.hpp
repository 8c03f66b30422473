#pragma once
/// @file
/// RestMonitor: whether the suturing task's two tools are at rest, asked by the task chart before
/// it calls the procedure done (charts/suturing.lua, root.Finishing): the motions' ends (the
/// trajectory's e_motion_done) say where the references stopped, not that the arms did — let go
/// of the thread's pull after the last push, the stick and the Endo Stitch spring back a few mm
/// onto their admittances' references.

#include <chrono>

#include <kdl/frames.hpp>

#include "cobra/core/component.hpp"
#include "cobra/core/request.hpp"

namespace cobra::components {

/// Decision component. Interface (SI):
/// - inputs `rightMeasPose`, `leftMeasPose` (KDL::Frame, m, any one frame for both: the Endo
///   Stitch's and the stick's measured tool poses);
/// - properties `tolerance` (m, > 0), `angle_tolerance` (rad, > 0), `window` (s, > 0): a tool is
///   at rest once its measured pose has stayed within `tolerance` and `angle_tolerance` of where it
///   was `window` s ago, i.e. moved slower than tolerance / window (default 0.1 mm in 0.2 s: 0.5
///   mm/s); both tools at rest is the answer;
/// - operation `askAtRest()` (void request): answered with `e_at_rest` once both tools have been at
///   rest for `window` s since the ask (not at once for tools that were still before it: a tool
///   only beginning to move as it is asked, the stick let go of the thread a step before, has
///   moved past the tolerance within the window); never answered while a tool moves (the chart
///   bounds the wait) or before both poses have arrived. A pose port that brings no new sample
///   counts as still.
/// Needs a periodic activity (the window is measured on its clock). updateHook allocates nothing.
class RestMonitor : public core::Component {
 public:
  explicit RestMonitor(std::string name);

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  /// One tool: where its current still spell began (the anchor) and since when.
  struct Tool {
    KDL::Frame anchor;
    std::chrono::nanoseconds since{0};
    bool seen = false;
  };
  /// Reads `port`'s newest sample into `tool`: a pose off the anchor by more than the tolerances
  /// starts a new still spell there.
  void watch(core::InputPort<KDL::Frame>& port, Tool& tool) noexcept;
  bool still(const Tool& tool) const noexcept;

  core::Property<double> tolerance_{"tolerance", 1e-4, "m", "how far a tool at rest may move within the window, > 0"};
  core::Property<double> angle_tolerance_{"angle_tolerance", 2e-3, "rad",
                                          "how far a tool at rest may turn within the window, > 0"};
  core::Property<double> window_{"window", 0.2, "s", "how long a tool must stay within the tolerances, > 0"};

  core::InputPort<KDL::Frame> right_{"rightMeasPose", "the Endo Stitch's measured tool pose", "m"};
  core::InputPort<KDL::Frame> left_{"leftMeasPose", "the stick's measured tool pose", "m"};

  core::PendingRequest ask_;
  bool asked_ = false;  // an askAtRest not answered yet
  std::chrono::nanoseconds asked_at_{0};  // when it was asked
  Tool right_tool_, left_tool_;
};

}  // namespace cobra::components
