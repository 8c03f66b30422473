// The puncturing task split over two hosts (split_procedure_test.cpp) with DDS Security on the
// link between them (puncturing.lua's `dds_security`: host needle is the identity host_a, host
// probe host_b, with the lab's test PKI that tools/make_test_pki.sh makes in the build tree):
// everything that crosses is encrypted and access-controlled, and the run is the same: the same
// lockstep meetings, so the same signals, sample for sample, and the same needle placements as
// the unsecured split run's. DDS domains 152..159, this test's own.

#include <gtest/gtest.h>

#include <cstdlib>

#include "split_hosts.hpp"

namespace cobra::run::testing {
namespace {

constexpr auto kRunLimit = std::chrono::seconds(600);  // wall time a host's run may take before it is killed

int domainFor(int test) { return 152 + static_cast<int>(::getpid() % 4) * 2 + test; }  // 152..159

void expectCompleted(HostProcess& p, int status) {
  const HostResult r = p.result();
  EXPECT_EQ(r.error, "") << p.setup().host;
  EXPECT_EQ(status, 0) << p.setup().host << ": " << r.outcome << ": " << r.reason;
  EXPECT_EQ(r.outcome, "completed") << p.setup().host << ": " << r.reason;
}

TEST(SplitSecured, TheSecuredSplitRunRecordsTheSameSignalsAndPlacementsAsTheUnsecuredOne) {
  ASSERT_EQ(std::system(COBRA_MAKE_TEST_PKI " " COBRA_TEST_PKI), 0);
  HostSetup secured_base;
  secured_base.domain = domainFor(0);
  secured_base.dds_security = COBRA_TEST_PKI;
  HostSetup plain_base;
  plain_base.domain = domainFor(1);
  // Both pairs at once: each host's process waits at the meetings for its peer much of the time.
  Pair secured("secured", secured_base);
  Pair plain("plain", plain_base);
  const int statuses[] = {secured.needle.wait(kRunLimit), secured.probe.wait(kRunLimit), plain.needle.wait(kRunLimit),
                          plain.probe.wait(kRunLimit)};
  expectCompleted(secured.needle, statuses[0]);
  expectCompleted(secured.probe, statuses[1]);
  expectCompleted(plain.needle, statuses[2]);
  expectCompleted(plain.probe, statuses[3]);

  const HostResult needle = secured.needle.result(), reference = plain.needle.result();
  ASSERT_FALSE(needle.placements.empty());
  EXPECT_EQ(needle.placements, reference.placements);
  EXPECT_EQ(needle.duration, reference.duration);
  for (const auto& [a, b] : {std::pair{&secured.needle, &plain.needle}, std::pair{&secured.probe, &plain.probe}}) {
    const auto with = signalLinesBefore(a->setup().folder / "report" / "signals.csv", 1e9);
    const auto without = signalLinesBefore(b->setup().folder / "report" / "signals.csv", 1e9);
    EXPECT_GT(with.size(), 3000u);
    ASSERT_EQ(with.size(), without.size()) << a->setup().host;
    for (std::size_t i = 0; i < with.size(); ++i) ASSERT_EQ(with[i], without[i]) << a->setup().host << " row " << i;
  }
  // The secured hosts knew each other by their certificates: no participant refused.
  for (const HostResult* host : {&needle, &reference})
    for (const std::string& line : host->log) EXPECT_EQ(line.find("refused participant"), std::string::npos) << line;
}

}  // namespace
}  // namespace cobra::run::testing
