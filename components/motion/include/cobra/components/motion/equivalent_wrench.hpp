#pragma once
/// @file
/// The thesis' Equivalent Wrench component (§6.2.3): moves a measured wrench to another
/// application point and/or reference frame through the adjoint (eq. 6.1-6.3).

#include <kdl/frames.hpp>

#include "cobra/core/component.hpp"

namespace cobra::components {

/// Calculation component. On every wrench arriving on `inWrench` (an event port; measured at the
/// origin of frame B, in B's axes), writes on `outWrench` the same wrench seen at frame C, where
/// C's pose relative to B is the last value of `referenceFrame`, or the property
/// `reference_frame` until that port has delivered one (e.g. the fixed sensor-to-tool-tip offset).
/// `change_application_point` and `change_reference_system` choose what changes (both: eq. 6.1).
/// With `invert_reference`, the frame given is B's pose relative to C instead — e.g. a robot's
/// measured tool pose in its base frame turns a tool-frame sensor wrench into base axes
/// (`change_application_point = false` keeps it at the tool point).
/// Real time: allocation-free.
class EquivalentWrench : public core::Component {
 public:
  explicit EquivalentWrench(std::string name);

 protected:
  void updateHook() override;

 private:
  core::InputPort<KDL::Wrench> in_wrench_{"inWrench", "wrench at B's origin, in B's axes", "N, N·m"};
  core::InputPort<KDL::Frame> reference_frame_port_{"referenceFrame", "pose of frame C relative to B", "m"};
  core::OutputPort<KDL::Wrench> out_wrench_{"outWrench", "the same wrench at C (see the properties)", "N, N·m"};
  core::Property<bool> change_application_point_{"change_application_point", true, "",
                                                  "take the torque about C's origin instead of B's"};
  core::Property<bool> change_reference_system_{"change_reference_system", true, "",
                                                 "express the wrench in C's axes instead of B's"};
  core::Property<KDL::Frame> reference_frame_{"reference_frame", KDL::Frame::Identity(), "m",
                                              "pose of C relative to B until referenceFrame delivers one"};
  core::Property<bool> invert_reference_{"invert_reference", false, "",
                                         "the frame given is B's pose relative to C (e.g. a measured tool pose)"};
  KDL::Frame frame_ = KDL::Frame::Identity();
  bool frame_from_port_ = false;
};

}  // namespace cobra::components
