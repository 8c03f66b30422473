#include "cobra/components/suturing/teleoperation_clutch.hpp"

#include <cmath>

namespace cobra::components {

TeleoperationClutch::TeleoperationClutch(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Haptic device engagement (thesis §5.5, InitHapticDevice): the tool follows the device's motion from "
                "where both were when the teleoperation started") {
  addProperty(scale_);
  addPort(master_);
  addPort(slave_);
  addPort(des_);
}

bool TeleoperationClutch::configureHook() {
  if (!(std::isfinite(scale_()) && scale_() > 0.0))
    return refuse("property scale is " + std::to_string(scale_()) + "; expected a finite value > 0");
  return true;
}

bool TeleoperationClutch::startHook() {
  engaged_ = have_slave_ = false;
  return true;
}

void TeleoperationClutch::updateHook() {
  if (slave_.read(slave_now_) != core::FlowStatus::NoData) have_slave_ = true;
  KDL::Frame master;
  const core::FlowStatus status = master_.read(master);
  if (status == core::FlowStatus::NoData || !have_slave_) return;
  if (!engaged_) {
    master0_ = master;
    slave0_ = slave_now_;
    engaged_ = true;
  } else if (status != core::FlowStatus::NewData) {
    return;
  }
  des_.write(KDL::Frame(master.M * master0_.M.Inverse() * slave0_.M,
                        slave0_.p + (master.p - master0_.p) * scale_()));
}

}  // namespace cobra::components
