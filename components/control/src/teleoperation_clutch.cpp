#include "cobra/components/control/teleoperation_clutch.hpp"

#include <chrono>
#include <cmath>

namespace cobra::components {

TeleoperationClutch::TeleoperationClutch(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Haptic device engagement (thesis §5.5, InitHapticDevice): the tool follows the device's motion from "
                "where both were when the teleoperation started") {
  addProperty(scale_);
  addProperty(engagement_time_);
  addProperty(smoothing_time_);
  addPort(master_);
  addPort(slave_);
  addPort(des_);
}

bool TeleoperationClutch::configureHook() {
  if (!(std::isfinite(scale_()) && scale_() > 0.0))
    return refuse("property scale is " + std::to_string(scale_()) + "; expected a finite value > 0");
  if (!(std::isfinite(engagement_time_()) && engagement_time_() >= 0.0))
    return refuse("property engagement_time is " + std::to_string(engagement_time_()) + " s; expected a finite value >= 0");
  if (!(std::isfinite(smoothing_time_()) && smoothing_time_() >= 0.0))
    return refuse("property smoothing_time is " + std::to_string(smoothing_time_()) + " s; expected a finite value >= 0");
  return true;
}

bool TeleoperationClutch::startHook() {
  engaged_ = have_slave_ = false;
  averaged_ = 0;
  master_sum_ = KDL::Vector::Zero();
  return true;
}

void TeleoperationClutch::updateHook() {
  if (slave_.read(slave_now_) != core::FlowStatus::NoData) have_slave_ = true;
  KDL::Frame master;
  const core::FlowStatus status = master_.read(master);
  if (!have_slave_) return;
  if (!engaged_) {
    // Until engaged: the tool's pose while no device sample came (e.g. behind a link's delay): a
    // coupling reading it sees no offset; from the first sample, while the samples of
    // engagement_time are averaged, the tool's pose then (the coupling holds the tool there, e.g.
    // against the thread's pull). A sample counts when new; the first also when it came before
    // the tool's pose did.
    if (status == core::FlowStatus::NewData || (status == core::FlowStatus::OldData && averaged_ == 0)) {
      if (averaged_ == 0) {
        first_sample_ = now();
        slave0_ = slave_now_;
      }
      master_sum_ += master.p;
      ++averaged_;
      if (std::chrono::duration<double>(now() - first_sample_).count() >= engagement_time_() - 1e-9) {
        master0_ = KDL::Frame(master.M, master_sum_ / static_cast<double>(averaged_));
        smoothed_ = master0_.p;
        last_sample_ = now();
        engaged_ = true;
      }
    }
    if (!engaged_) {
      des_.write(averaged_ == 0 ? slave_now_ : slave0_);
      return;
    }
  } else if (status != core::FlowStatus::NewData) {
    return;
  } else if (smoothing_time_() > 0.0) {
    // First order on the samples' own timing: a tracker's frames come at their rate, not ours.
    const double dt = std::chrono::duration<double>(now() - last_sample_).count();
    last_sample_ = now();
    smoothed_ += (master.p - smoothed_) * (1.0 - std::exp(-dt / smoothing_time_()));
  } else {
    smoothed_ = master.p;
  }
  des_.write(KDL::Frame(master.M * master0_.M.Inverse() * slave0_.M, slave0_.p + (smoothed_ - master0_.p) * scale_()));
}

}  // namespace cobra::components
