// The far process of dds_process_test: on DDS domain argv[1], echoes every KDL.Frame from topic
// "peer/pose_in" to "peer/pose_out" (moved 1 m along x) and answers every event of
// "peer/events_in" with "ack_<name>" on "peer/events_out"; exits 0 after the event "quit",
// 2 after 8 s without it.
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <thread>

#include <kdl/frames.hpp>

#include "cobra/core/port.hpp"
#include "cobra/dds/dds_transport.hpp"

int main(int argc, char** argv) {
  using namespace cobra;
  if (argc != 2) {
    std::cerr << "usage: dds_peer DOMAIN\n";
    return 1;
  }
  dds::registerDdsTransport({std::atoi(argv[1]), "cobra_peer", true});
  core::ConnPolicy data = core::ConnPolicy::data();
  data.transport = "dds";
  core::ConnPolicy events = core::ConnPolicy::buffer(16);
  events.transport = "dds";
  events.options = {{"reliability", "reliable"}, {"depth", "16"}};

  core::InputPort<KDL::Frame> pose_in("pose_in", "", "m");
  core::OutputPort<KDL::Frame> pose_out("pose_out", "", "m");
  core::InputPort<core::Event> events_in("events_in", "", "");
  core::OutputPort<core::Event> events_out("events_out", "", "");
  data.topic = "peer/pose_in";
  core::connectToTransport(pose_in, data);
  data.topic = "peer/pose_out";
  core::connectToTransport(pose_out, data);
  events.topic = "peer/events_in";
  core::connectToTransport(events_in, events);
  events.topic = "peer/events_out";
  core::connectToTransport(events_out, events);

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(8);
  while (std::chrono::steady_clock::now() < deadline) {
    KDL::Frame frame;
    if (pose_in.read(frame) == core::FlowStatus::NewData) {
      frame.p.x(frame.p.x() + 1.0);
      pose_out.write(frame);
    }
    core::Event event;
    while (events_in.read(event) == core::FlowStatus::NewData) {
      if (event.name == "quit") return 0;
      core::Event ack = event;
      ack.name.assign("ack_" + event.name.str());
      ack.source = "peer";
      events_out.write(ack);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return 2;
}
