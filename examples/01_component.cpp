// Example 01: write a component, give it ports, a property and an operation, and run it.
//
// A component is a class deriving from cobra::core::Component. Its interface is made of
// members (ports, properties) registered in the constructor, plus operations. Its behaviour
// is in hooks: configureHook, startHook, updateHook, stopHook, cleanupHook, exceptionHook.
// Here: a first-order low-pass filter, y += (u - y)·dt/(τ + dt), stepped at 100 Hz on the
// lockstep clock (simulated time, deterministic, as fast as the CPU allows).

#include <cstdio>

#include "cobra/core/core.hpp"

using namespace cobra::core;
using namespace std::chrono_literals;

class LowPass : public Component {
 public:
  explicit LowPass(std::string name) : Component(std::move(name), Role::Calculation, "First-order low-pass filter") {
    addPort(input_);
    addPort(output_);
    addProperty(time_constant_.range(1e-6, 100.0));
    // Operations are callable by name (from C++ now; from Lua and the console later).
    addOperation("reset", &LowPass::reset, this, "sets the filter state to a value").arg("value", "1", "new state");
  }

 protected:
  bool configureHook() override {
    std::printf("  configureHook: tau = %g s\n", time_constant_());
    return true;
  }
  void updateHook() override {
    const double dt = std::chrono::duration<double>(activity().period()).count();  // s
    double u = 0.0;
    if (input_.read(u) != FlowStatus::NoData) y_ += (u - y_) * dt / (time_constant_() + dt);
    output_.write(y_);
  }

 private:
  void reset(double value) { y_ = value; }

  InputPort<double> input_{"u", "filter input", "1"};
  OutputPort<double> output_{"y", "filtered output", "1"};
  Property<double> time_constant_{"tau", 0.1, "s", "time constant of the filter"};
  double y_ = 0.0;
};

int main() {
  LowPass filter("Filter");
  OutputPort<double> step{"step", "a unit step", "1"};
  InputPort<double> response{"response", "the filter output", "1"};
  connect(step, static_cast<InputPort<double>&>(filter.port("u")));
  connectPorts(filter.port("y"), response, ConnPolicy::buffer(100));

  LockstepClock clock;
  clock.add(filter, 10ms);
  filter.setProperty("tau", 0.05);
  std::printf("lifecycle: %s", std::string(toString(filter.state())).c_str());
  if (!filter.configure() || !filter.start()) return 1;
  std::printf(" -> %s\n", std::string(toString(filter.state())).c_str());

  step.write(1.0);
  clock.advance(200ms);  // 20 updates
  double y = 0.0;
  int n = 0;
  while (response.read(y) == FlowStatus::NewData) ++n;
  std::printf("after %d updates (200 ms) the step response is %.4f (1 - exp(-4) = 0.9817 for a continuous filter)\n", n, y);

  filter.call("reset", 0.0);
  clock.advance(10ms);
  response.read(y);
  std::printf("after reset(0) and one update: %.4f\n", y);

  try {
    filter.setProperty("tau", "fast");
  } catch (const Error& e) {
    std::printf("bad input is refused: %s\n", e.what());
  }
  std::printf("%s", toText(describe(filter)).c_str());
  return filter.stop() ? 0 : 1;
}
