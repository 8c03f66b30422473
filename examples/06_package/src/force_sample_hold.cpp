#include "force_sample_hold.hpp"

namespace example {

ForceSampleHold::ForceSampleHold(std::string name)
    : Component(std::move(name), cobra::core::Role::Calculation, "Holds the latest force sample it receives") {
  addPort(sample_in_);
  addPort(sample_out_);
  addProperty(sample_);
  addProperty(received_.readOnly());
}

bool ForceSampleHold::startHook() {
  held_ = sample_();
  received_.setFromOwner(0);
  return true;
}

void ForceSampleHold::updateHook() {
  int received = 0;
  while (sample_in_.read(held_) == cobra::core::FlowStatus::NewData) ++received;
  if (received == 0) return;
  received_.setFromOwner(received_() + received);
  sample_out_.write(held_);
}

}  // namespace example
