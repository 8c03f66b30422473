// Two processes on this host: the test forks and execs dds_peer, which echoes a KDL.Frame and
// answers events over the dds transport (DDS domain 118, this test's own).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cobra/core/port.hpp"
#include "dds_test_support.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;
using test::event;
constexpr int kDomain = 118;

TEST(DdsProcesses, AFrameAndEventsCrossToAnotherProcessAndBack) {
  const pid_t peer = fork();
  ASSERT_GE(peer, 0);
  if (peer == 0) {
    const std::string domain = std::to_string(kDomain);
    execl(COBRA_DDS_PEER, COBRA_DDS_PEER, domain.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  struct KillOnFailure {
    pid_t pid;
    bool reaped = false;
    ~KillOnFailure() {
      if (!reaped) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
      }
    }
  } guard{peer};
  test::RegisteredTransport dds("dds", kDomain, "cobra_test");
  core::OutputPort<KDL::Frame> pose_out("pose_out", "", "m");
  core::InputPort<KDL::Frame> pose_in("pose_in", "", "m");
  core::OutputPort<core::Event> events_out("events_out", "", "");
  core::InputPort<core::Event> events_in("events_in", "", "");
  core::ConnPolicy events = core::ConnPolicy::buffer(16);
  events.options = {{"reliability", "reliable"}, {"depth", "16"}};
  core::connectToTransport(pose_out, dds.policy("peer/pose_in"));
  core::connectToTransport(pose_in, dds.policy("peer/pose_out"));
  core::connectToTransport(events_out, dds.policy("peer/events_in", events));
  core::connectToTransport(events_in, dds.policy("peer/events_out", events));
  for (const char* topic : {"peer/pose_in", "peer/pose_out", "peer/events_in", "peer/events_out"})
    ASSERT_TRUE(dds.transport->waitForMatch(topic, 6s)) << topic;

  const KDL::Frame frame(KDL::Rotation::RotZ(0.5), KDL::Vector(0.1, 0.2, 0.3));
  KDL::Frame echoed;
  // A data connection: write until the echo comes (the first write may precede the peer's reader).
  ASSERT_TRUE(test::pollUntil([&] {
    pose_out.write(frame);
    return pose_in.read(echoed) == core::FlowStatus::NewData;
  }));
  EXPECT_TRUE(KDL::Equal(echoed, KDL::Frame(frame.M, frame.p + KDL::Vector(1.0, 0, 0)), 1e-12));

  for (const char* name : {"e_needle_inserted", "e_probe_placed", "e_done"}) events_out.write(event(name));
  std::vector<std::string> answers;
  ASSERT_TRUE(test::pollUntil([&] {
    core::Event e;
    while (events_in.read(e) == core::FlowStatus::NewData) answers.push_back(e.name.str() + "@" + e.source.str());
    return answers.size() >= 3;
  }));
  EXPECT_EQ(answers, (std::vector<std::string>{"ack_e_needle_inserted@peer", "ack_e_probe_placed@peer", "ack_e_done@peer"}));

  events_out.write(event("quit"));
  int status = 0;
  ASSERT_TRUE(test::pollUntil([&] { return waitpid(peer, &status, WNOHANG) == peer; }, 9s));
  guard.reaped = true;
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace cobra::dds
