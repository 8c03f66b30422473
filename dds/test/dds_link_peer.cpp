// The processes of dds_link_test: each has a DdsLink (the package's component, linked here).
//   dds_link_peer live DOMAIN NAME PEERS LEASE [INITIAL_PEERS [LEAVE_AFTER [HOW]]]
//     configures and starts a DdsLink, prints the events it sends (one "name source" a line),
//     and waits to be killed (exits 2 after 20 s). With LEAVE_AFTER (s), it leaves that long
//     after its first e_peer_joined instead: stops and cleans up its link (a wall-clock link says
//     farewell), prints "left", exits 0. HOW "done" (default): its run completed (setDone(true)
//     first, as `cobra run` does), "failed": it did not (the farewell says not done).
//   dds_link_peer lockstep DOMAIN ROLE INSTANTS DROP_SHARE TRACE_FILE [MEETING_PERIOD]
//     one half of a lockstep run of INSTANTS instants of 1 ms, its clock met through its DdsLink:
//     ROLE "leader" (participant "leader") steps Mover, which writes a KDL.Frame on "link/pose"
//     at every step (x = step * 1 mm) and reads the events of "link/ticks"; ROLE "follower" steps
//     Follower, which reads "link/pose" and writes the event e_tick_<step> on "link/ticks" every
//     7th step. Each writes what its component read, one line per step, to TRACE_FILE.
//     ROLES "late-leader" and "late-follower" make their input's connection (ticks, pose) only
//     after INSTANTS / 4 instants, as a deployment switch would make it mid-run. MEETING_PERIOD:
//     the DdsLink's meeting_period (s; default 0, every instant).
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <thread>

#include <kdl/frames.hpp>

#include "cobra/core/component.hpp"
#include "cobra/core/activity.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/dds/dds_link.hpp"

namespace {

using namespace cobra;

core::ConnPolicy policy(const std::string& topic, core::ConnPolicy base) {
  base.transport = "dds";
  base.topic = topic;
  base.options = {{"reliability", "reliable"}, {"depth", "64"}};
  return base;
}

/// Writes its pose and reads the follower's ticks; traces what it read.
class Mover final : public core::Component {
 public:
  explicit Mover(std::ostream& trace) : Component("Mover", core::Role::Calculation, "writes a pose"), trace_(trace) {
    addPort(pose_);
    addPort(ticks_);
  }

 protected:
  void updateHook() override {
    core::Event e;
    trace_ << step_ << ':';
    while (ticks_.read(e) == core::FlowStatus::NewData) trace_ << ' ' << e.name.str();
    trace_ << '\n';
    pose_.write(KDL::Frame(KDL::Vector(0.001 * static_cast<double>(step_), 0, 0)));
    ++step_;
  }

 public:
  core::OutputPort<KDL::Frame> pose_{"pose", "a pose", "m"};
  core::InputPort<core::Event> ticks_{"ticks", "the follower's ticks", ""};

 private:
  std::ostream& trace_;
  long step_ = 0;
};

/// Reads the leader's pose, writes a tick every 7th step; traces what it read.
class Follower final : public core::Component {
 public:
  explicit Follower(std::ostream& trace)
      : Component("Follower", core::Role::Calculation, "follows a pose"), trace_(trace) {
    addPort(pose_);
    addPort(ticks_);
  }

 protected:
  void updateHook() override {
    KDL::Frame f;
    trace_ << step_ << ':';
    if (pose_.read(f) == core::FlowStatus::NewData) trace_ << ' ' << std::lround(f.p.x() * 1000.0);
    trace_ << '\n';
    if (step_ % 7 == 0) {
      core::Event e;
      e.name.assign("e_tick_" + std::to_string(step_));
      ticks_.write(e);
    }
    ++step_;
  }

 public:
  core::InputPort<KDL::Frame> pose_{"pose", "the leader's pose", "m"};
  core::OutputPort<core::Event> ticks_{"ticks", "ticks", ""};

 private:
  std::ostream& trace_;
  long step_ = 0;
};

bool configured(core::Component& c) {
  const core::Result r = c.configure();
  if (!r) std::cerr << r.message << '\n';
  return static_cast<bool>(r);
}

int live(int domain, const std::string& name, const std::string& peers, const std::string& lease,
         const std::string& initial_peers, double leave_after, bool done) {
  dds::registerLinkedTransport();
  dds::DdsLink link("Link");
  link.property("initial_peers").setFromText(initial_peers);
  link.property("domain").setFromText(std::to_string(domain));
  link.property("participant").setFromText(name);
  link.property("peers").setFromText(peers);
  link.property("lease").setFromText(lease);
  core::InputPort<core::Event> events("events", "", "");
  core::connect(link.events(), events, core::ConnPolicy::buffer(16));
  if (!configured(link) || !link.start()) return 1;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::optional<std::chrono::steady_clock::time_point> leave_at;
  while (std::chrono::steady_clock::now() < until) {  // says what it sees: a test in another namespace reads it
    static_cast<core::SlaveActivity&>(link.activity()).step();  // the link writes its queued events
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) {
      std::cout << e.name.str() << ' ' << e.source.str() << std::endl;
      if (leave_after >= 0.0 && !leave_at && e.name.str() == "e_peer_joined")
        leave_at = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                           std::chrono::duration<double>(leave_after));
    }
    if (leave_at && std::chrono::steady_clock::now() >= *leave_at) {
      link.setDone(done);
      if (!link.stop() || !link.cleanup()) return 1;
      std::cout << "left" << std::endl;
      return 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return 2;
}

int lockstep(int domain, const std::string& role, long instants, const std::string& drop, const std::string& file,
             const std::string& meeting_period) {
  dds::registerLinkedTransport();
  std::ofstream trace(file);
  const bool late = role.starts_with("late-");
  const bool leader = role == "leader" || role == "late-leader";
  core::LockstepClock clock;
  dds::DdsLink link("Link");
  link.property("domain").setFromText(std::to_string(domain));
  link.property("participant").setFromText(leader ? "leader" : "follower");
  link.property("peers").setFromText(leader ? "follower" : "leader");
  link.property("lease").setFromText("2");
  link.property("drop_share").setFromText(drop);
  link.property("meeting_period").setFromText(meeting_period);
  clock.add(link, std::chrono::nanoseconds(0));  // a LockstepActivity: the transport goes lockstep
  if (!configured(link)) return 1;
  Mover mover(trace);
  Follower follower(trace);
  core::Component& component = leader ? static_cast<core::Component&>(mover) : follower;
  clock.add(component, std::chrono::milliseconds(1));
  if (leader) {
    core::connectToTransport(mover.pose_, policy("link/pose", core::ConnPolicy::data()));
    if (!late) core::connectToTransport(mover.ticks_, policy("link/ticks", core::ConnPolicy::buffer(64)));
  } else {
    if (!late) core::connectToTransport(follower.pose_, policy("link/pose", core::ConnPolicy::data()));
    core::connectToTransport(follower.ticks_, policy("link/ticks", core::ConnPolicy::buffer(64)));
  }
  if (!configured(component) || !link.start() || !component.start()) return 1;
  clock.setClockSync(&link);
  for (long i = 0; i < instants; ++i) {
    if (late && i == instants / 4) {
      if (leader) core::connectToTransport(mover.ticks_, policy("link/ticks", core::ConnPolicy::buffer(64)));
      else core::connectToTransport(follower.pose_, policy("link/pose", core::ConnPolicy::data()));
    }
    clock.advance(std::chrono::milliseconds(1));
  }
  // Meet until the peer is done too, so that neither leaves while the other still needs it.
  link.setDone(true);
  while (!link.peersDone()) clock.advance(std::chrono::milliseconds(1));
  clock.setClockSync(nullptr);
  if (!component.stop() || !link.stop()) return 1;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // retransmissions the peer may need
  return link.lostPeers().empty() ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "live" && argc >= 6 && argc <= 9 && (argc < 9 || std::string(argv[8]) == "done" || std::string(argv[8]) == "failed"))
    return live(std::atoi(argv[2]), argv[3], argv[4], argv[5], argc >= 7 ? argv[6] : "", argc >= 8 ? std::atof(argv[7]) : -1.0,
                argc < 9 || std::string(argv[8]) == "done");
  if (mode == "lockstep" && (argc == 7 || argc == 8))
    return lockstep(std::atoi(argv[2]), argv[3], std::atol(argv[4]), argv[5], argv[6], argc == 8 ? argv[7] : "0");
  std::cerr << "usage: dds_link_peer live DOMAIN NAME PEERS LEASE [INITIAL_PEERS [LEAVE_AFTER]] | lockstep DOMAIN ROLE "
               "INSTANTS DROP_SHARE TRACE_FILE [MEETING_PERIOD]\n";
  return 1;
}
