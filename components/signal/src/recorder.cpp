#include "cobra/components/signal/recorder.hpp"

namespace cobra::components {

Recorder::Recorder(std::string name)
    : Component(std::move(name), core::Role::Bridge, "Records (time, value) samples of a signal in memory") {
  addEventPort(in_);
  addProperty(capacity_.range(1, 100'000'000));
  addProperty(dropped_.readOnly());
  addOperation("count", std::function<int()>([this] { return count(); }), "number of samples recorded so far");
  addOperation("clear", &Recorder::clear, this, "forgets the samples recorded so far (keeps the buffer)");
}

void Recorder::clear() {
  samples_.clear();
  dropped_.setFromOwner(0);
}

bool Recorder::configureHook() {
  samples_.clear();
  samples_.reserve(static_cast<std::size_t>(capacity_()));
  dropped_.setFromOwner(0);
  return true;
}

void Recorder::updateHook() {
  double value = 0.0;
  while (in_.read(value) == core::FlowStatus::NewData) {
    if (samples_.size() < samples_.capacity()) samples_.push_back({std::chrono::duration<double>(now()).count(), value});
    else dropped_.setFromOwner(dropped_() + 1);
  }
}

}  // namespace cobra::components
