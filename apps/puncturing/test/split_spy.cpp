// The eavesdropper of split_secured_test: `split_spy DOMAIN OUT SECONDS` joins DDS domain DOMAIN
// without security and reads the needle chart's events that cross to host probe (topic
// NeedleTaskSup/outputEvents) for SECONDS, writing how many it read to OUT after each.
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <thread>

#include "cobra/core/port.hpp"
#include "cobra/dds/dds_transport.hpp"

int main(int argc, char** argv) {
  using namespace cobra;
  if (argc != 4) {
    std::cerr << "usage: split_spy DOMAIN OUT SECONDS\n";
    return 1;
  }
  dds::registerDdsTransport({std::atoi(argv[1]), "spy", false});
  core::InputPort<core::Event> events("events", "the needle chart's events, overheard", "");
  core::ConnPolicy policy = core::ConnPolicy::buffer(4096);
  policy.transport = "dds";
  policy.topic = "NeedleTaskSup/outputEvents";
  core::connectToTransport(events, policy);
  std::ofstream(argv[2]) << 0 << std::endl;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(argv[3]));
  int heard = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    core::Event e;
    bool any = false;
    while (events.read(e) == core::FlowStatus::NewData) ++heard, any = true;
    if (any) std::ofstream(argv[2]) << heard << std::endl;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return 0;
}
