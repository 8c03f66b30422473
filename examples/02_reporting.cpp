// Example 02: record ports to a CSV file with the Reporter.
//
// The Reporter (cobra::components::Reporter, a Bridge) samples chosen output ports at its own
// activity's period and writes one CSV row per update in which some port had new data. Its
// readers are connected with a `data` policy, so the components it records never wait for it,
// and the file is written by a low-priority thread of its own, so neither does its update.
// Here: Sine -> Gain, both recorded, on the lockstep clock (simulated time: the file is the same
// at every run).

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cobra/components/reporting/reporter.hpp"
#include "cobra/components/signal/gain.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/core/core.hpp"

using namespace cobra;
using namespace std::chrono_literals;

int main() {
  core::ComponentRegistry registry;
  auto& sine = registry.make<components::SineGenerator>("Sine");
  auto& gain = registry.make<components::Gain>("Gain");
  auto& reporter = registry.make<components::Reporter>("Reporter");
  sine.setProperty("frequency", 50.0);  // Hz
  gain.setProperty("k", 2.5);
  core::connectPorts(sine.port("out"), gain.port("in"));

  // Choose what to record before configure: a port by reference, or by "Component.port".
  reporter.reportPort(sine.port("out"));
  reporter.reportPort(registry, "Gain.out");
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "cobra_example_02.csv";
  reporter.setProperty("file_path", file.string());
  // Mistakes are refused with a message that says what to do.
  try {
    reporter.reportPort(gain.port("in"));
  } catch (const core::Error& e) {
    std::printf("refused: %s\n", e.what());
  }

  // The Reporter samples at its own period: 2 ms here, every other sample of the 1 kHz sine.
  // It is added last so that each row holds the values written in the same instant.
  core::LockstepClock clock;
  clock.add(sine, 1ms);
  clock.add(gain, 1ms);
  clock.add(reporter, 2ms);
  for (core::Component* c : registry.components()) {
    if (const core::Result r = c->configure(); !r) return std::printf("%s\n", r.message.c_str()), 1;
    if (const core::Result r = c->start(); !r) return std::printf("%s\n", r.message.c_str()), 1;
  }
  clock.advance(100ms);
  // stop() drains the Reporter's queue into the file and flushes it: the file is complete now.
  if (!reporter.stop()) return 1;

  std::printf("recorded %s (rows dropped: %d); its first lines:\n", file.string().c_str(),
              reporter.getProperty<int>("rows_dropped"));
  std::ifstream in(file);
  std::string line;
  int rows = 0;
  for (; std::getline(in, line); ++rows)
    if (rows < 6) std::printf("  %s\n", line.c_str());
  std::printf("  ... %d lines in all (a header and one row per 2 ms)\n", rows);
  std::filesystem::remove(file);
  return rows == 51 ? 0 : 1;
}
