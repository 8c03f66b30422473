// DdsLink: the transport's participant comes from it (a dds connection before it is configured
// is refused), one per process, its properties checked; peer liveliness across two processes
// (kill -9 the peer: e_peer_lost from the survivor); the lockstep clock met across two processes
// (traces identical between runs and equal to a one-step delay, also with 10 % of the data
// messages dropped); a peer that leaves on the wall clock after its run completed is done, not
// lost, one that leaves otherwise is lost at once; a peer stalled past the lease is not lost when
// it comes back within `lapse_grace`; `priority` puts the DDS threads on SCHED_FIFO. The peer
// processes are dds_link_peer. DDS domains 128..134, 136..138, 140 and 142..145, this test's own.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "cobra/core/activity.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/dds/dds_link.hpp"
#include "cobra/test_support/test_support.hpp"
#include "dds_test_support.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;

/// A child process running dds_link_peer with `args`; killed and reaped unless waited for.
class Peer : public test::ChildProcess {
 public:
  /// `output`: a file for the child's stdout and stderr ("": the test's own).
  explicit Peer(std::vector<std::string> args, const std::string& output = "")
      : ChildProcess(withProgram(std::move(args)), output) {}

 private:
  static std::vector<std::string> withProgram(std::vector<std::string> args) {
    args.insert(args.begin(), COBRA_DDS_LINK_PEER);
    return args;
  }
};

void set(core::Component& c, const std::string& property, const std::string& value) {
  c.property(property).setFromText(value);
}

TEST(DdsLink, ADdsConnectionBeforeTheLinkIsConfiguredIsRefusedNamingIt) {
  registerLinkedTransport();
  core::OutputPort<double> out("out", "", "1");
  core::InputPort<double> in("in", "", "1");
  core::ConnPolicy policy = core::ConnPolicy::data();
  policy.transport = "dds";
  policy.topic = "link/refused";
  EXPECT_EQ(test_support::messageOf([&] { core::connectPorts(out, in, policy); }),
            "cannot connect out (double) to in (double): cannot connect in over transport \"dds\": no DdsLink is "
            "configured in this process; create one (package cobra_dds, type DdsLink) and configure it before making "
            "dds connections");

  DdsLink link("Link");
  set(link, "domain", "128");
  set(link, "participant", "alone");
  ASSERT_TRUE(link.configure()) << link.configure().message;
  ASSERT_NE(link.transport(), nullptr);
  core::connectPorts(out, in, policy);  // now over the link's participant
  ASSERT_TRUE(link.transport()->waitForMatch("link/refused", 5s));
  double got = 0;
  ASSERT_TRUE(test::pollUntil([&] {
    out.write(1.5);
    return in.read(got) == core::FlowStatus::NewData;
  }));
  EXPECT_EQ(got, 1.5);

  DdsLink second("Link2");
  set(second, "domain", "128");
  set(second, "participant", "other");
  EXPECT_EQ(second.configure().message,
            "component 'Link2': another DdsLink ('Link') is configured in this process; one per process");
  core::disconnectPorts(out, in);
  ASSERT_TRUE(link.cleanup());
  EXPECT_EQ(link.transport(), nullptr);
  EXPECT_NE(test_support::messageOf([&] { core::connectPorts(out, in, policy); }).find("no DdsLink is configured"),
            std::string::npos);
}

/// The ids of this process's threads.
std::set<pid_t> threadIds() {
  std::set<pid_t> ids;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
    ids.insert(static_cast<pid_t>(std::stol(task.path().filename().string())));
  return ids;
}

// `priority`: the threads Fast DDS makes for the participant run SCHED_FIFO at it (they inherit
// it from the configuring thread, whose own scheduling comes back), and so does a writer end's.
TEST(DdsLink, PriorityPutsTheParticipantsThreadsOnSchedFifo) {
  sched_param fifo{};
  fifo.sched_priority = 7;
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &fifo) != 0) GTEST_SKIP() << "SCHED_FIFO refused here";
  sched_param other{};
  ASSERT_EQ(pthread_setschedparam(pthread_self(), SCHED_OTHER, &other), 0);
  registerLinkedTransport();
  const std::set<pid_t> before = threadIds();
  DdsLink link("Link");
  set(link, "domain", "144");
  set(link, "participant", "fifo");
  set(link, "priority", "7");
  ASSERT_TRUE(link.configure());
  core::OutputPort<double> out("out", "", "1");
  core::ConnPolicy policy = core::ConnPolicy::data();
  policy.transport = "dds";
  policy.topic = "link/fifo";
  ASSERT_NO_THROW(core::connectToTransport(out, policy));  // a writer end, with its thread
  int scheduler = -1;
  sched_param mine{};
  ASSERT_EQ(pthread_getschedparam(pthread_self(), &scheduler, &mine), 0);
  EXPECT_EQ(scheduler, SCHED_OTHER) << "the configuring thread's scheduling came back";
  // The threads made since, and those not at SCHED_FIFO 7 (by name); a writer end's thread sets
  // its priority when it starts.
  int made = 0;
  std::string others;
  ASSERT_TRUE(test::pollUntil([&] {
    made = 0;
    others.clear();
    for (const pid_t id : threadIds()) {
      if (before.count(id) != 0) continue;
      ++made;
      sched_param p{};
      if (sched_getscheduler(id) == SCHED_FIFO && sched_getparam(id, &p) == 0 && p.sched_priority == 7) continue;
      std::ifstream comm("/proc/self/task/" + std::to_string(id) + "/comm");
      std::string name;
      std::getline(comm, name);
      others += " " + name;
    }
    return others.empty();
  }, 2s)) << "threads made for the participant not on SCHED_FIFO 7:" << others;
  EXPECT_GT(made, 2) << "Fast DDS's threads and the writer end's";
  EXPECT_NE(test_support::messageOf([&] { set(link, "priority", "100"); }).find("priority"), std::string::npos);
}

TEST(DdsLink, BadPropertiesAreRefusedNamingTheProperty) {
  registerLinkedTransport();
  DdsLink link("Link");
  set(link, "domain", "129");
  set(link, "participant", "needle");
  set(link, "peers", "probe, needle");
  EXPECT_EQ(link.configure().message, "component 'Link': property 'peers' lists this process's own participant 'needle'");
  set(link, "peers", "probe");
  set(link, "initial_peers", "10.0.0.2, localhost");
  EXPECT_EQ(link.configure().message,
            "component 'Link': dds participant 'needle': initial peer 'localhost' is not an IPv4 address (expected e.g. "
            "10.0.0.2)");
  EXPECT_NE(test_support::messageOf([&] { set(link, "drop_share", "1.5"); }).find("drop_share"), std::string::npos);
  set(link, "initial_peers", "127.0.0.1");
  set(link, "participant", "");
  EXPECT_EQ(link.configure().message,
            "component 'Link': property 'participant' is empty: name this process, e.g. \"needle\"");
}

/// This process's side of a wall-clock pair: DdsLink "survivor" in `domain` with the peer "peer"
/// and a lease of 0.1 s (or `lease`), and what its events port said ("event@source").
struct Survivor {
  static constexpr double kLease = 0.1;  // s

  explicit Survivor(const std::string& domain, const std::string& lease = "0.1") {
    registerLinkedTransport();
    set(link, "domain", domain);
    set(link, "participant", "survivor");
    set(link, "peers", "peer");
    set(link, "lease", lease);
    core::connectPorts(link.events(), events, core::ConnPolicy::buffer(16));
  }
  bool start() { return link.configure() && link.start(); }
  /// Steps the link (its default SlaveActivity: the test's thread is the link's thread), which
  /// writes the events its foreign threads queued, and reads them; true when `wanted` is among
  /// all those seen.
  bool saw(const std::string& wanted) {
    static_cast<core::SlaveActivity&>(link.activity()).step();
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) seen.push_back(e.name.str() + "@" + e.source.str());
    return std::find(seen.begin(), seen.end(), wanted) != seen.end();
  }
  long times(const std::string& event) {
    saw("");
    return std::count(seen.begin(), seen.end(), event);
  }

  DdsLink link{"Link"};
  core::InputPort<core::Event> events{"events", "", ""};
  std::vector<std::string> seen;
};

TEST(DdsLink, KillingThePeerGivesOneLostEventWithinTheLease) {
  Peer peer({"live", "130", "peer", "survivor", "0.1"});
  Survivor survivor("130");
  ASSERT_TRUE(survivor.start());
  ASSERT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_joined@peer"); }, 8s));

  const auto killed = std::chrono::steady_clock::now();
  peer.killHard();
  ASSERT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_lost@peer"); }, std::chrono::milliseconds(1000)));
  const double delay = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  std::cout << "e_peer_lost " << delay * 1e3 << " ms after kill -9 (lease " << Survivor::kLease * 1e3 << " ms)\n";
  EXPECT_LT(delay, 10 * Survivor::kLease);
  EXPECT_EQ(survivor.link.lostPeers(), std::vector<std::string>{"peer"});
  EXPECT_EQ(survivor.link.operation("lostPeers").invokeFromText({}), "peer");
  std::this_thread::sleep_for(3 * std::chrono::duration<double>(Survivor::kLease));
  EXPECT_EQ(survivor.times("e_peer_lost@peer"), 1);
}

// Wall clock: a peer whose run completed (setDone) says farewell (done) when it cleans up its
// link, before its writer goes, so its leaving is not a loss; kill -9 (the test above) still is.
TEST(DdsLink, APeerThatLeavesNormallyOnTheWallClockIsDoneNotLost) {
  Peer peer({"live", "136", "peer", "survivor", "0.1", "", "0.3"});
  Survivor survivor("136");
  ASSERT_TRUE(survivor.start());
  ASSERT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_joined@peer"); }, 8s));
  EXPECT_EQ(survivor.link.operation("joinedPeers").invokeFromText({}), "peer");
  EXPECT_FALSE(survivor.link.peersDone()) << "the peer is still there";
  EXPECT_EQ(peer.wait(5s), 0) << "the peer left normally (stopped and cleaned up its link)";
  // Its liveliness ended with its writer: a loss would be reported within the lease.
  std::this_thread::sleep_for(10 * std::chrono::duration<double>(Survivor::kLease));
  EXPECT_EQ(survivor.times("e_peer_lost@peer"), 0);
  EXPECT_EQ(survivor.link.lostPeers(), std::vector<std::string>{});
  EXPECT_EQ(survivor.link.operation("lostPeers").invokeFromText({}), "");
  EXPECT_TRUE(survivor.link.peersDone()) << "a peer that said farewell is done";
}

// The link's events happen on Fast DDS's threads: they wait in a queue until the link's own step
// writes them on its events port (one writer thread, as every port has).
TEST(DdsLink, EventsOfFastDdsThreadsReachThePortInTheLinksOwnStep) {
  Peer peer({"live", "145", "peer", "survivor", "0.1"});
  Survivor survivor("145");
  ASSERT_TRUE(survivor.start());
  ASSERT_TRUE(test::pollUntil([&] { return survivor.link.operation("joinedPeers").invokeFromText({}) == "peer"; }, 8s));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the listener's call that emits it has returned
  core::Event e;
  EXPECT_EQ(survivor.events.read(e), core::FlowStatus::NoData) << "written by a thread that is not the link's";
  EXPECT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_joined@peer"); }, 1s));  // steps the link
  EXPECT_EQ(survivor.link.droppedEvents(), 0U);
}

// Wall clock: a peer that leaves before its run completed (an error, a safe stop: no setDone)
// says farewell not done, and is lost at once, naming why: with a lease of 5 s, well before its
// liveliness could lapse.
TEST(DdsLink, APeerThatLeavesBeforeItsRunCompletedIsLostAtOnceNamingWhy) {
  Peer peer({"live", "143", "peer", "survivor", "5", "", "0.3", "failed"});
  Survivor survivor("143", "5");
  ASSERT_TRUE(survivor.start());
  ASSERT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_joined@peer"); }, 8s));
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(peer.wait(5s), 0) << "the peer left (stopped and cleaned up its link)";
  EXPECT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_lost@peer"); }, 1s)) << "lost within 1 s (lease 5 s)";
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("cobra dds: participant 'survivor' lost its peer 'peer': it left before its run completed (its "
                      "link's farewell said not done: an error, a safe stop or a time limit there)"),
            std::string::npos)
      << said;
  EXPECT_EQ(survivor.link.lostPeers(), std::vector<std::string>{"peer"});
  EXPECT_EQ(survivor.times("e_peer_lost@peer"), 1);
}

// `lapse_grace`: a peer stalled past the lease (SIGSTOP, as a process held up at its start)
// whose liveliness comes back within the grace is not lost; one that stays silent (killed) is,
// within lease + grace, naming both.
TEST(DdsLink, APeerStalledPastTheLeaseThatComesBackWithinTheGraceIsNotLost) {
  // Lease 0.5 s, grace 1.5 s: a loaded machine's own delays (tenths of s) stay well inside them.
  Peer peer({"live", "145", "peer", "survivor", "0.5"});
  Survivor survivor("145", "0.5");
  set(survivor.link, "lapse_grace", "1.5");
  ASSERT_TRUE(survivor.start());
  ASSERT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_joined@peer"); }, 8s));
  peer.stall(1000ms);  // twice the lease
  std::this_thread::sleep_for(2s);
  EXPECT_EQ(survivor.times("e_peer_lost@peer"), 0) << "a stall of 1 s, back within the grace";

  ::testing::internal::CaptureStderr();
  const auto killed = std::chrono::steady_clock::now();
  peer.killHard();
  EXPECT_TRUE(test::pollUntil([&] { return survivor.saw("e_peer_lost@peer"); }, 5s));
  const double delay = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  const std::string said = ::testing::internal::GetCapturedStderr();
  std::cout << "e_peer_lost " << delay * 1e3 << " ms after kill -9 (lease 500 ms, grace 1500 ms)\n";
  EXPECT_GE(delay, 1.5) << "not before the grace";
  EXPECT_NE(said.find("cobra dds: participant 'survivor' lost its peer 'peer': its liveliness lapsed (lease 0.5 s) "
                      "and did not come back within 1.5 s"),
            std::string::npos)
      << said;
}

/// What the leader and the follower of dds_link_peer read at each of `instants` steps when a
/// sample written at step k is read at step k + 1 (the one-step delay of the clock meetings).
/// `connected_at`: the instant from which the inputs' connections exist (they read only what
/// is written from then on). `period`: the meeting period in steps; a sample written at step j
/// is read from the first meeting instant after it, ceil((j + 1) / period) * period.
std::pair<std::string, std::string> predictedTraces(long instants, long connected_at = 0, long period = 1) {
  std::ostringstream leader, follower;
  for (long k = 0; k < instants; ++k) {
    leader << k << ':';
    const bool meeting = k >= period && k % period == 0;  // the samples of steps [k - period, k) arrive
    if (meeting)
      for (long j = std::max(k - period, connected_at); j < k; ++j)
        if (j % 7 == 0) leader << " e_tick_" << j;
    leader << '\n';
    follower << k << ':';
    if (meeting && k - 1 >= connected_at) follower << ' ' << k - 1;
    follower << '\n';
  }
  return {leader.str(), follower.str()};
}

std::string readFile(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream all;
  all << in.rdbuf();
  return all.str();
}

/// Runs the two halves of a lockstep run of `instants` on `domain`; their traces.
std::pair<std::string, std::string> runSplit(int domain, long instants, const std::string& drop, const std::string& tag,
                                             const std::string& leader_role = "leader",
                                             const std::string& follower_role = "follower",
                                             const std::string& meeting_period = "0") {
  const auto dir = std::filesystem::temp_directory_path() / ("cobra_dds_link_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto leader_file = dir / (tag + "_leader.txt"), follower_file = dir / (tag + "_follower.txt");
  const auto started = std::chrono::steady_clock::now();
  Peer leader({"lockstep", std::to_string(domain), leader_role, std::to_string(instants), drop, leader_file.string(),
               meeting_period});
  Peer follower({"lockstep", std::to_string(domain), follower_role, std::to_string(instants), drop,
                 follower_file.string(), meeting_period});
  EXPECT_EQ(leader.wait(60s), 0);
  EXPECT_EQ(follower.wait(10s), 0);
  std::cout << tag << ": " << instants << " instants met across two processes in "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() << " s\n";
  auto traces = std::make_pair(readFile(leader_file), readFile(follower_file));
  std::filesystem::remove_all(dir);
  return traces;
}

/// "" when `a` and `b` are equal, else their first differing line (traces are long).
std::string firstDifference(const std::string& a, const std::string& b) {
  std::istringstream in_a(a), in_b(b);
  std::string line_a, line_b;
  for (int line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(in_a, line_a));
    const bool more_b = static_cast<bool>(std::getline(in_b, line_b));
    if (!more_a && !more_b) return "";
    if (more_a != more_b || line_a != line_b)
      return "line " + std::to_string(line) + ": '" + (more_a ? line_a : "(end)") + "' vs '" + (more_b ? line_b : "(end)") + "'";
  }
}

/// The first `instants` lines of `trace` (the run meets once or twice more to end together).
std::string head(const std::string& trace, long instants) {
  std::size_t at = 0;
  for (long i = 0; i < instants && at != std::string::npos; ++i) {
    at = trace.find('\n', at);
    if (at != std::string::npos) ++at;
  }
  return trace.substr(0, at);
}

TEST(DdsLink, TwoProcessesInLockstepGiveIdenticalTracesWithAOneStepDelay) {
  constexpr long kInstants = 2000;
  const auto first = runSplit(131, kInstants, "0", "run1");
  const auto second = runSplit(131, kInstants, "0", "run2");
  EXPECT_EQ(firstDifference(first.first, second.first), "");
  EXPECT_EQ(firstDifference(first.second, second.second), "");
  const auto predicted = predictedTraces(kInstants);
  EXPECT_EQ(firstDifference(head(first.first, kInstants), predicted.first), "");
  EXPECT_EQ(firstDifference(head(first.second, kInstants), predicted.second), "");
}

// Dropped discovery packets may make a reader match its writer after the writer's first
// heartbeat; a volatile reader then skipped the samples sent before, and the meeting passed
// without them (1 run in 7 read nothing at instant 1). Lockstep ends are transient-local.
TEST(DdsLink, TracesStayIdenticalWithATenthOfTheDataMessagesDropped) {
  constexpr long kInstants = 2000;
  const auto predicted = predictedTraces(kInstants);
  for (const char* tag : {"lossy1", "lossy2", "lossy3"}) {
    const auto lossy = runSplit(132, kInstants, "0.1", tag);
    EXPECT_EQ(firstDifference(head(lossy.first, kInstants), predicted.first), "") << tag;
    EXPECT_EQ(firstDifference(head(lossy.second, kInstants), predicted.second), "") << tag;
  }
}

// Connections made mid-run (a deployment switch) on both sides: each reader matches a writer
// that has sent for a while. As with a local connection, the inputs read only what is written
// from then on (the transient-local writer sends its history of 64 events again: they are
// ignored), from the next instant, and the run stays in step.
TEST(DdsLink, ConnectionsMadeMidRunReadWhatIsWrittenFromThenOn) {
  constexpr long kInstants = 2000;
  const auto late = runSplit(138, kInstants, "0", "late", "late-leader", "late-follower");
  const auto predicted = predictedTraces(kInstants, kInstants / 4);
  EXPECT_EQ(firstDifference(head(late.first, kInstants), predicted.first), "");
  EXPECT_EQ(firstDifference(head(late.second, kInstants), predicted.second), "");
}

// meeting_period 5 ms: the processes meet at every 5th instant; a sample crosses at the first
// meeting after it was written (up to 5 steps late), still identically run after run.
TEST(DdsLink, AMeetingPeriodDelaysSamplesToTheNextMeetingInstant) {
  constexpr long kInstants = 2000;
  const auto first = runSplit(142, kInstants, "0", "period1", "leader", "follower", "0.005");
  const auto second = runSplit(142, kInstants, "0", "period2", "leader", "follower", "0.005");
  const auto predicted = predictedTraces(kInstants, 0, 5);
  EXPECT_EQ(firstDifference(head(first.first, kInstants), predicted.first), "");
  EXPECT_EQ(firstDifference(head(first.second, kInstants), predicted.second), "");
  EXPECT_EQ(firstDifference(first.first, second.first), "");
  EXPECT_EQ(firstDifference(first.second, second.second), "");
}

}  // namespace
}  // namespace cobra::dds

namespace cobra::dds {
namespace {

// Two processes with different meeting periods would each wait at instants the other never
// meets at: each loses the other at once, naming both periods.
TEST(DdsLink, PeersWithDifferentMeetingPeriodsAreLostNamingBoth) {
  const auto dir = std::filesystem::temp_directory_path() / ("cobra_dds_link_period_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string log = (dir / "leader.log").string();
  Peer leader({"lockstep", "140", "leader", "200", "0", (dir / "leader.txt").string(), "0.005"}, log);
  Peer follower({"lockstep", "140", "follower", "200", "0", (dir / "follower.txt").string(), "0"});
  EXPECT_EQ(leader.wait(30s), 3);
  EXPECT_EQ(follower.wait(30s), 3);
  const std::string said = readFile(log);
  EXPECT_NE(said.find("participant 'leader' lost its peer 'follower': it meets every instant, participant 'leader' "
                      "every 5 ms: give both DdsLinks the same meeting_period"),
            std::string::npos)
      << said;
  std::filesystem::remove_all(dir);
}

TEST(DdsLink, APeerKilledInALockstepRunIsLostAndTheOtherRunsOn) {
  const auto dir = std::filesystem::temp_directory_path() / ("cobra_dds_link_kill_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string log = (dir / "leader.log").string();
  Peer leader({"lockstep", "133", "leader", "8000", "0", (dir / "leader.txt").string()}, log);
  Peer follower({"lockstep", "133", "follower", "8000", "0", (dir / "follower.txt").string()});
  ASSERT_TRUE(test::pollUntil([&] { return std::filesystem::exists(dir / "follower.txt") &&
                                           std::filesystem::file_size(dir / "follower.txt") > 2000; }, 10s));
  follower.killHard();
  EXPECT_EQ(leader.wait(30s), 3);  // ran its 8,000 instants, the last ones alone, with a lost peer
  const std::string said = readFile(log);
  EXPECT_NE(said.find("participant 'leader' lost its peer 'follower': "), std::string::npos) << said;
  EXPECT_NE(readFile(dir / "leader.txt").find("\n7999:"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cobra::dds

namespace cobra::dds {
namespace {

TEST(DdsLink, ALivePeerThatMissesAMeetingForItsTimeoutIsLost) {
  const auto dir = std::filesystem::temp_directory_path() / ("cobra_dds_link_miss_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string log = (dir / "leader.log").string();
  // The "follower" is alive (its liveliness holds) but runs no clock: it never meets.
  Peer follower({"live", "134", "follower", "leader", "2"});
  Peer leader({"lockstep", "134", "leader", "50", "0", (dir / "leader.txt").string()}, log);
  EXPECT_EQ(leader.wait(20s), 3);
  const std::string said = readFile(log);
  EXPECT_NE(said.find("participant 'leader' lost its peer 'follower': it missed the meeting at t = 0.001 s for 2 s"),
            std::string::npos)
      << said;
  std::filesystem::remove_all(dir);
}

// A peer in another DDS domain (or unreachable) never comes to the first meeting: given up after
// join_timeout, the message naming both participants and this one's domain.
TEST(DdsLink, APeerThatNeverComesIsLostNamingBothParticipantsAndTheDomain) {
  registerLinkedTransport();
  core::LockstepClock clock;
  DdsLink link("Link");
  set(link, "domain", "137");
  set(link, "participant", "needle");
  set(link, "peers", "probe");  // nobody is "probe" in domain 137
  set(link, "join_timeout", "0.3");
  clock.add(link, std::chrono::nanoseconds(0));
  ASSERT_TRUE(link.configure());
  ASSERT_TRUE(link.start());
  clock.setClockSync(&link);
  testing::internal::CaptureStderr();
  clock.advance(1ms);
  const std::string said = testing::internal::GetCapturedStderr();
  clock.setClockSync(nullptr);
  EXPECT_EQ(link.lostPeers(), std::vector<std::string>{"probe"});
  EXPECT_TRUE(link.peersDone()) << "a lost peer is not waited for";
  EXPECT_NE(said.find("participant 'needle' lost its peer 'probe': it never came to participant 'needle' in DDS domain "
                      "137 (join_timeout 0.3 s): is it running, with the same DdsLink.domain, and reachable"),
            std::string::npos)
      << said;
  EXPECT_TRUE(link.stop());
}

}  // namespace
}  // namespace cobra::dds
