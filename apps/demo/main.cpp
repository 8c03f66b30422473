// cobra demo: a small deployment on the lockstep clock.
//
//   SineGenerator (1 kHz) --out-> Gain --out-> Recorder
//                                      \-> ThresholdDetector --events-> (printed)
//
// It runs 20 ms of simulated time, changes the gain while running (a configuration change,
// applied between two updates), runs 20 ms more, shows that bad input is refused, and prints
// what happened.

#include <cstdio>
#include <stdexcept>

#include "cobra/components/signal/gain.hpp"
#include "cobra/components/signal/recorder.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/components/signal/threshold_detector.hpp"
#include "cobra/core/core.hpp"
#include "cobra/deploy/graph.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace cobra;
using namespace std::chrono_literals;

namespace {

void printEvents(core::InputPort<core::Event>& events) {
  core::Event event;
  while (events.read(event) == core::FlowStatus::NewData)
    std::printf("  event %-20s from %-10s at t = %5.1f ms\n", event.name.str().c_str(), event.source.str().c_str(),
                std::chrono::duration<double, std::milli>(event.stamp).count());
}

}  // namespace

int main() {
  core::ComponentRegistry registry;
  auto& sine = registry.make<components::SineGenerator>("Sine");
  auto& gain = registry.make<components::Gain>("Gain");
  auto& recorder = registry.make<components::Recorder>("Recorder");
  auto& detector = registry.make<components::ThresholdDetector>("Detector");

  sine.setProperty("frequency", 50.0);  // Hz: one period every 20 ms
  sine.setProperty("amplitude", 1.0);
  gain.setProperty("k", 2.0);
  detector.setProperty("threshold", 1.5);
  detector.setProperty("hysteresis", 0.2);

  core::connectPorts(sine.port("out"), gain.port("in"));
  core::connectPorts(gain.port("out"), recorder.port("in"), core::ConnPolicy::buffer(16));
  core::connectPorts(gain.port("out"), detector.port("in"), core::ConnPolicy::buffer(16));

  // The demo itself listens to every component's events, as a supervisor would.
  core::InputPort<core::Event> events{"events", "events of all components", ""};
  for (core::Component* c : registry.components()) core::connectPorts(c->port("events"), events, core::ConnPolicy::buffer(64));

  core::LockstepClock clock;
  clock.add(sine, 1ms);    // periodic: 1 kHz in simulated time
  clock.add(gain, 0ns);    // event-driven: runs when a sample arrives
  clock.add(recorder, 0ns);
  clock.add(detector, 0ns);
  for (core::Component* c : registry.components()) {
    if (auto r = c->configure(); !r) return std::fprintf(stderr, "%s\n", r.message.c_str()), 1;
    if (auto r = c->start(); !r) return std::fprintf(stderr, "%s\n", r.message.c_str()), 1;
  }

  std::printf("cobra demo: Sine -> Gain -> Recorder + Detector on the lockstep clock\n\n");
  for (core::Component* c : registry.components()) std::printf("%s", core::toText(core::describe(*c)).c_str());

  std::printf("\n[0, 20) ms with k = 2:\n");
  clock.advance(20ms);
  printEvents(events);

  std::printf("\nset Gain.k = 0.5 while running (applied between two updates)\n");
  gain.setProperty("k", 0.5);
  std::printf("[20, 40) ms with k = 0.5: the detector never fires\n");
  clock.advance(20ms);
  printEvents(events);

  std::printf("\nrecorded %zu samples (every 4th shown):\n", recorder.samples().size());
  std::printf("  %8s  %9s\n", "t [ms]", "y");
  for (std::size_t i = 0; i < recorder.samples().size(); i += 4)
    std::printf("  %8.1f  %+9.4f\n", recorder.samples()[i].time * 1e3, recorder.samples()[i].value);

  std::printf("\nsetting an out-of-range property is refused and changes nothing:\n");
  try {
    sine.setProperty("frequency", -3.0);
  } catch (const core::Error& e) {
    std::printf("  error: %s\n", e.what());
  }
  std::printf("  Sine.frequency is still %s Hz\n", sine.property("frequency").valueText().c_str());

  // A drawing of the deployment (components coloured by role), as `cobra graph` makes.
  const auto dot_path = std::filesystem::temp_directory_path() / "cobra-demo.dot";
  const auto svg_path = std::filesystem::temp_directory_path() / "cobra-demo.svg";
  std::ofstream(dot_path) << deploy::graphvizDot(registry, "cobra demo");
  const std::string render = "dot -Tsvg '" + dot_path.string() + "' -o '" + svg_path.string() + "' 2>/dev/null";
  if (std::system(render.c_str()) == 0)
    std::printf("\nthe deployment is drawn in %s (Graphviz source: %s)\n", svg_path.c_str(), dot_path.c_str());
  else
    std::printf("\nthe deployment's Graphviz source is %s (install graphviz to render it)\n", dot_path.c_str());

  std::printf("\n%llu component updates in %.0f ms of simulated time; states:",
              static_cast<unsigned long long>(clock.steps()), std::chrono::duration<double, std::milli>(clock.now()).count());
  for (core::Component* c : registry.components())
    std::printf(" %s=%s", c->name().c_str(), std::string(core::toString(c->state())).c_str());
  std::printf("\n");
  return 0;
}
