#include "cobra/components/signal/sine_generator.hpp"

#include <cmath>
#include <numbers>

namespace cobra::components {

SineGenerator::SineGenerator(std::string name)
    : Component(std::move(name), core::Role::Calculation, "Sine wave: offset + amplitude·sin(2π·frequency·t + phase)") {
  addPort(out_);
  addProperty(amplitude_);
  addProperty(frequency_.range(0.0, 1e6));
  addProperty(phase_);
  addProperty(offset_);
}

bool SineGenerator::startHook() {
  start_ = now();
  return true;
}

void SineGenerator::updateHook() {
  const double t = std::chrono::duration<double>(now() - start_).count();
  out_.write(offset_() + amplitude_() * std::sin(2.0 * std::numbers::pi * frequency_() * t + phase_()));
}

}  // namespace cobra::components
