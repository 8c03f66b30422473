#include "force_low_pass.hpp"

#include <cmath>
#include <numbers>

namespace example {

ForceLowPass::ForceLowPass(std::string name)
    : Component(std::move(name), cobra::core::Role::Calculation, "First-order low-pass filter of a force") {
  addPort(force_in_);
  addPort(force_out_);
  addPort(sample_out_);
  addProperty(cutoff_frequency_);
  addProperty(initial_force_);
}

bool ForceLowPass::configureHook() {
  if (!(cutoff_frequency_() > 0.0)) return refuse("cutoff_frequency must be > 0 Hz");
  return true;
}

bool ForceLowPass::startHook() {
  filtered_ = input_ = initial_force_();
  count_ = 0;
  last_update_ = now();
  return true;
}

void ForceLowPass::updateHook() {
  force_in_.read(input_);  // keeps the previous force when nothing was written yet
  const double dt = std::chrono::duration<double>(now() - last_update_).count();  // s
  last_update_ = now();
  filtered_ += (1.0 - std::exp(-2.0 * std::numbers::pi * cutoff_frequency_() * dt)) * (input_ - filtered_);
  force_out_.write(filtered_);
  sample_out_.write(ForceSample{input_, filtered_, ++count_});
}

}  // namespace example
