#include "cobra/components/signal/gain.hpp"

namespace cobra::components {

Gain::Gain(std::string name) : Component(std::move(name), core::Role::Calculation, "Scales its input: y = k·u") {
  addEventPort(in_);
  addPort(out_);
  addProperty(k_);
}

void Gain::updateHook() {
  double u = 0.0;
  while (in_.read(u) == core::FlowStatus::NewData) out_.write(k_() * u);
}

}  // namespace cobra::components
