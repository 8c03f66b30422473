// The puncturing task split over two hosts on the wall clock (issue 21: "and wall-clock mode"):
// host needle and host probe each run their half with threaded activities (`cobra run
// apps/puncturing --host NAME --realtime`), joined by DDS without clock meetings: a sample is
// sent within the link's poll period (0.1 ms) of its write and read when it arrives. The whole
// procedure takes about 82 s of wall time, too long here: the run is bounded by a time limit of
// kStretch s, long enough for each chart to pass a state that waits for an event of the other
// host's chart. Both runs then end at their time limit; the host that ends first leaves
// normally (its link says farewell), so the other does not report it lost.

#include <gtest/gtest.h>

#include <tuple>

#include "split_hosts.hpp"

namespace cobra::run::testing {
namespace {

constexpr double kStretch = 20.0;                       // s of wall time each host runs
constexpr auto kRunLimit = std::chrono::seconds(180);  // loading both halves, then the stretch

int domain() { return 220 + static_cast<int>(::getpid() % 10); }  // 220..229: this test's own

}  // namespace

TEST(SplitRealtime, TwoHostsOnTheWallClockExchangeEventsAndEndAtTheTimeLimit) {
  HostSetup base;
  base.domain = domain();
  base.realtime = true;
  base.time_limit = kStretch;
  Pair pair("realtime", base);
  const int needle_status = pair.needle.wait(kRunLimit);
  const int probe_status = pair.probe.wait(kRunLimit);
  const HostResult needle = pair.needle.result(), probe = pair.probe.result();
  for (const auto& [host, r, status] : {std::tuple{"needle", &needle, needle_status}, {"probe", &probe, probe_status}}) {
    ASSERT_EQ(r->error, "") << host;
    std::printf("[split realtime] host %s: %s after %.3f s (%s)\n", host, r->outcome.c_str(), r->duration,
                r->reason.c_str());
    EXPECT_EQ(status, 1) << host << ": 1, the time limit; " << r->outcome << ": " << r->reason;
    EXPECT_EQ(r->outcome, "time limit") << host << ": " << r->reason;
    EXPECT_GE(r->duration, kStretch) << host;
    EXPECT_LT(r->duration, kStretch + 1.0) << host << ": it ended at its time limit";
    EXPECT_TRUE(logged(*r, std::string("peer joined: '") + (r == &needle ? "probe" : "needle") + "'"))
        << host << ": the other host joined";
    EXPECT_FALSE(logged(*r, "Link: e_peer_lost")) << host << ": the other host left normally";
    EXPECT_FALSE(loggedStart(*r, "peer lost")) << host;
  }
  // Each chart passed a state that only an event of the other host's chart ends: the probe moves
  // once the needle waits for it (e_needle_wait_us), the needle goes on once the probe is on the
  // skin (e_us_positioned).
  EXPECT_TRUE(loggedStart(probe, "us > root.MoveToSkin")) << "the probe never left Idle: no e_needle_wait_us from host needle";
  EXPECT_TRUE(loggedStart(needle, "needle > root.InsertingNeedles"))
      << "the needle never left WaitUSPositioning: no e_us_positioned from host probe";
  EXPECT_EQ(needle.final_states.count("us"), 0u) << "the ultrasound chart is host probe's";
  expectTrackingClearanceAndTanksHeld(pair, needle, probe);
}

}  // namespace cobra::run::testing
