// The runner on one host of an application split over two (run/test/apps/split): the run table's
// entries of the other host left out and said, the peers told when this host's charts ended (one
// more clock meeting before the run ends), and a lost peer ending the run with its own outcome
// and exit status. The clock sync is the test's (TestLink); the transport records the ends.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "cobra/core/clock_sync.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/deploy/package_registry.hpp"
#include "cobra/run/runner.hpp"

namespace cobra::run {
namespace {

const std::filesystem::path kApp = std::filesystem::path(COBRA_SOURCE_DIR) / "run" / "test" / "apps" / "split";

/// What the test's link did and is to do (one link per run).
struct LinkScript {
  int meetings = 0;
  int meetings_after_done = 0;
  int lose_peer_at = -1;  ///< meeting from which peer "b" is lost (-1: never)
};
LinkScript g_link;

/// A clock sync whose peer is done at once, or lost at a given meeting.
class TestLink final : public core::Component, public core::ClockSync {
 public:
  explicit TestLink(std::string name) : Component(std::move(name), core::Role::Bridge, "test clock sync") {}
  void reached(std::chrono::nanoseconds) noexcept override {
    ++g_link.meetings;
    if (done_) ++g_link.meetings_after_done;
  }
  void setDone(bool done) noexcept override { done_ = done; }
  bool peersDone() const noexcept override { return true; }
  std::vector<std::string> lostPeers() const override {
    if (g_link.lose_peer_at >= 0 && g_link.meetings >= g_link.lose_peer_at) return {"b"};
    return {};
  }

 private:
  bool done_ = false;
};

class NullWire final : public core::Transport {
 public:
  void check(const core::ConnPolicy&) const override {}
  void makeWriterEnd(core::OutputPortBase&, const core::ConnPolicy&, core::PortBase*) override {}
  void makeReaderEnd(core::InputPortBase&, const core::ConnPolicy&, core::PortBase*) override {}
};

class SplitRunner : public ::testing::Test {
 protected:
  void SetUp() override {
    core::TransportRegistry::add("split_test_wire", "test", "split_runner_test", std::make_shared<NullWire>());
    g_link = {};
  }
  void TearDown() override { core::TransportRegistry::remove("split_test_wire"); }
  static RunOptions options() {
    RunOptions o;
    o.app = kApp / "split.lua";
    o.host = "a";
    o.time_limit = 5.0;
    o.add_packages = [](deploy::PackageRegistry& packages) {
      packages.addBuiltin("split_test_parts", [](deploy::PackageBuilder& package) {
        package.component<TestLink>("TestLink", "test clock sync");
      });
    };
    return o;
  }
};

TEST_F(SplitRunner, TheOtherHostsEntriesAreSaidAndThePeersHearThatThisHostEnded) {
  std::vector<std::string> lines;
  RunOptions o = options();
  o.progress = [&](const std::string& line) { lines.push_back(line); };
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  EXPECT_EQ(exitStatus(r), 0);
  EXPECT_EQ(r.final_states.size(), 1u) << "the remote chart is host b's";
  EXPECT_EQ(r.log.front(), "observed on host b: run.charts 'remote'");
  EXPECT_TRUE(std::any_of(lines.begin(), lines.end(), [](const std::string& l) {
    return l.find("this host's charts ended; waiting for its peers") != std::string::npos;
  }));
  EXPECT_EQ(g_link.meetings_after_done, 1) << "one meeting tells the peers, then the run ends";
  EXPECT_EQ(g_link.meetings, static_cast<int>(std::lround(r.duration / 0.001))) << "one meeting per 1 ms step";
}

TEST_F(SplitRunner, ALostPeerEndsTheRunAsPeerLostWithExitStatus3) {
  g_link.lose_peer_at = 100;  // 0.1 s: before the chart is done (about 0.33 s)
  const RunResult r = runApp(options());
  EXPECT_EQ(r.outcome, Outcome::PeerLost);
  EXPECT_EQ(exitStatus(r), 3);
  EXPECT_EQ(r.reason, "peer 'b' lost at   0.100 s; this host's charts had completed");
  EXPECT_NE(std::find(r.log.begin(), r.log.end(), "peer lost: 'b'"), r.log.end());
  EXPECT_EQ(endLine(r), "cobra run: peer lost: " + r.reason);
}

TEST_F(SplitRunner, WithoutAHostThePlacementIsIgnoredAndBothChartsRunHere) {
  RunOptions o = options();
  o.host.clear();
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  EXPECT_EQ(r.final_states.size(), 2u);
  EXPECT_EQ(g_link.meetings, 0) << "no placement in force: the link is no clock sync";
  EXPECT_TRUE(std::none_of(r.log.begin(), r.log.end(), [](const std::string& l) { return l.rfind("observed", 0) == 0; }));
}

}  // namespace
}  // namespace cobra::run
