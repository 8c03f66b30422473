#include "cobra/components/signal/constant.hpp"

namespace cobra::components {

Constant::Constant(std::string name)
    : Component(std::move(name), core::Role::Calculation, "Writes the value of its property at every update") {
  addPort(out_);
  addProperty(value_);
}

void Constant::updateHook() { out_.write(value_()); }

}  // namespace cobra::components
