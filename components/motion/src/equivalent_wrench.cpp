#include "cobra/components/motion/equivalent_wrench.hpp"

#include "cobra/kinematics/geometry.hpp"

namespace cobra::components {

EquivalentWrench::EquivalentWrench(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Equivalent wrench (thesis §6.2.3): a wrench moved to another application point and/or frame") {
  addEventPort(in_wrench_);
  addPort(reference_frame_port_);
  addPort(out_wrench_);
  addProperty(change_application_point_);
  addProperty(change_reference_system_);
  addProperty(reference_frame_);
  addProperty(invert_reference_);
}

void EquivalentWrench::updateHook() {
  KDL::Frame frame;
  if (reference_frame_port_.read(frame) != core::FlowStatus::NoData) {
    frame_ = frame;
    frame_from_port_ = true;
  } else if (!frame_from_port_) {
    frame_ = reference_frame_();
  }
  const kinematics::WrenchChange change{change_application_point_(), change_reference_system_()};
  KDL::Wrench wrench;
  const KDL::Frame c_in_b = invert_reference_() ? frame_.Inverse() : frame_;
  while (in_wrench_.read(wrench) == core::FlowStatus::NewData)
    out_wrench_.write(kinematics::equivalentWrench(c_in_b, wrench, change));
}

}  // namespace cobra::components
