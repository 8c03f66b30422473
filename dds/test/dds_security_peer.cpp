// The far process of dds_security_test: usage `dds_security_peer DOMAIN PKI ROLE OUT SECONDS`,
// PKI the folder tools/make_test_pki.sh made. Its identity and behaviour by ROLE:
//   host_b, plain_b    host probe of a split run, with DDS Security (host_b's certificate and
//                      permissions) or without (plain_b): echoes every KDL.Frame of
//                      "ISUR/measCartPose" on "UR5/measCartPose" (moved 1 m along x) and answers
//                      every event of "NeedleTaskSup/outputEvents" with "ack_<name>" on
//                      "ProbeTaskSup/outputEvents"; ends after the event "quit" (exit 0), or
//                      after SECONDS without it (exit 2);
//   unsecured, other_ca, no_permission, forged_permissions
//                      a rogue (no security; a complete setup of the rogue CA; a test CA identity
//                      whose permissions grant no topic of a run; that identity with permissions
//                      granting host_b's topics, signed by the rogue CA): until SIGTERM (then exit
//                      0), or for SECONDS, it reads "ISUR/measCartPose" (a measured pose) and
//                      writes the event "e_rogue_command" on "ProbeTaskSup/outputEvents" (a command
//                      to the needle chart) every 10 ms.
// It writes to OUT, each line flushed as it is known: "guid <its participant's GUID prefix>",
// "reader <ok or the error>", "writer <ok or the error>", then at the end "wrote <n>" (a rogue's
// commands written), "read <n>" (the poses it read) and (a rogue) "end terminated" (by SIGTERM)
// or "end after SECONDS".
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <thread>

#include <kdl/frames.hpp>

#include "cobra/core/port.hpp"
#include "cobra/dds/dds_transport.hpp"

namespace {

using namespace cobra;
using Security = dds::DdsTransport::Security;

Security securityOf(const std::string& pki, const std::string& role) {
  const auto f = [&](const std::string& name) { return pki + "/" + name; };
  if (role == "host_b")
    return {f("ca.crt"), f("host_b.crt"), f("host_b.key"), f("governance.p7s"), f("permissions_host_b.p7s"), ""};
  if (role == "other_ca")
    return {f("rogue_ca.crt"), f("rogue.crt"), f("rogue.key"), f("rogue_governance.p7s"), f("rogue_permissions.p7s"), ""};
  if (role == "no_permission")
    return {f("ca.crt"), f("noperm.crt"), f("noperm.key"), f("governance.p7s"), f("permissions_noperm.p7s"), ""};
  if (role == "forged_permissions")
    return {f("ca.crt"),           f("noperm.crt"),         f("noperm.key"), f("rogue_governance.p7s"),
            f("forged_permissions.p7s"), f("rogue_ca.crt")};
  return {};  // plain_b, unsecured
}

/// "ok", or the error connecting `port` to `topic`.
template <class Port>
std::string connect(Port& port, const std::string& topic, core::ConnPolicy policy) {
  policy.transport = "dds";
  policy.topic = topic;
  try {
    core::connectToTransport(port, policy);
    return "ok";
  } catch (const std::exception& e) {
    return e.what();
  }
}

/// Set by SIGTERM: the test ends a rogue once it watched it long enough.
volatile std::sig_atomic_t terminated = 0;
void onTerm(int) { terminated = 1; }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: dds_security_peer DOMAIN PKI ROLE OUT SECONDS\n";
    return 1;
  }
  const std::string role = argv[3];
  std::ofstream out(argv[4]);
  const auto seconds = std::chrono::duration<double>(std::atof(argv[5]));
  dds::DdsTransport::Options options{std::atoi(argv[1]), "cobra_" + role, true};
  options.udp_only = true;
  options.security = securityOf(argv[2], role);
  std::signal(SIGTERM, onTerm);  // may run on any thread of the process (Fast DDS's too): it only sets the flag
  const auto transport = dds::registerDdsTransport(options);
  out << "guid " << transport->guidPrefix() << std::endl;
  core::ConnPolicy events = core::ConnPolicy::buffer(16);
  events.options = {{"reliability", "reliable"}, {"depth", "16"}};

  core::InputPort<KDL::Frame> pose_in("pose_in", "", "m");
  core::OutputPort<core::Event> events_out("events_out", "", "");
  out << "reader " << connect(pose_in, "ISUR/measCartPose", core::ConnPolicy::data()) << std::endl;
  out << "writer " << connect(events_out, "ProbeTaskSup/outputEvents", events) << std::endl;
  const auto deadline = std::chrono::steady_clock::now() + seconds;
  int read = 0, wrote = 0;
  if (role == "host_b" || role == "plain_b") {
    core::OutputPort<KDL::Frame> pose_out("pose_out", "", "m");
    core::InputPort<core::Event> events_in("events_in", "", "");
    connect(pose_out, "UR5/measCartPose", core::ConnPolicy::data());
    connect(events_in, "NeedleTaskSup/outputEvents", events);
    while (std::chrono::steady_clock::now() < deadline) {
      KDL::Frame frame;
      if (pose_in.read(frame) == core::FlowStatus::NewData) {
        ++read;
        frame.p.x(frame.p.x() + 1.0);
        pose_out.write(frame);
      }
      core::Event event;
      while (events_in.read(event) == core::FlowStatus::NewData) {
        if (event.name == "quit") {
          out << "read " << read << std::endl;
          return 0;
        }
        core::Event ack = event;
        ack.name.assign("ack_" + event.name.str());
        ack.source.assign(role);
        events_out.write(ack);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    out << "read " << read << std::endl;
    return 2;
  }
  core::Event command;
  command.name = "e_rogue_command";
  command.source.assign(role);
  while (terminated == 0 && std::chrono::steady_clock::now() < deadline) {
    KDL::Frame frame;
    if (pose_in.read(frame) == core::FlowStatus::NewData) ++read;
    events_out.write(command);
    ++wrote;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  out << "wrote " << wrote << std::endl;
  out << "read " << read << std::endl;
  out << "end " << (terminated != 0 ? "terminated" : "after SECONDS") << std::endl;
  return 0;
}
