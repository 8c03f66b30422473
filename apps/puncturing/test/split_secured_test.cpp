// The puncturing task split over two hosts (split_procedure_test.cpp) with DDS Security on the
// link between them (puncturing.lua's `dds_security`: host needle is the identity host_a, host
// probe host_b, with the lab's test PKI that tools/make_test_pki.sh makes in the build tree):
// everything that crosses is encrypted and access-controlled, and the procedure is the same: both
// charts done, the needle placed as the unsecured split run places it (run side by side), while
// an eavesdropper hears the unsecured run and nothing of the secured one. DDS domains 152..159,
// this test's own.

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "split_hosts.hpp"

namespace cobra::run::testing {
namespace {

constexpr auto kRunLimit = std::chrono::seconds(600);  // wall time a host's run may take before it is killed

int domainFor(int test) { return 152 + static_cast<int>(::getpid() % 4) * 2 + test; }  // 152..159

/// An eavesdropper (split_spy, a process of its own: this one forks the hosts' processes, and no
/// DDS thread may exist in a process that forks): a participant without security in `domain`,
/// reading the needle chart's events that cross to host probe.
class Spy {
 public:
  Spy(int domain, const std::string& name) : out_(folderFor(name + ".txt")) {
    std::filesystem::create_directories(out_.parent_path());
    const std::string d = std::to_string(domain), o = out_.string();
    pid_ = ::fork();
    if (pid_ == 0) {
      ::execl(COBRA_SPLIT_SPY, COBRA_SPLIT_SPY, d.c_str(), o.c_str(), "1200", static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~Spy() {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  Spy(const Spy&) = delete;
  Spy& operator=(const Spy&) = delete;
  /// The events it read so far; -1 before it joined.
  int heard() const {
    int count = -1;
    std::ifstream(out_) >> count;
    return count;
  }

 private:
  std::filesystem::path out_;
  pid_t pid_ = -1;
};

void expectCompleted(HostProcess& p, int status) {
  const HostResult r = p.result();
  EXPECT_EQ(r.error, "") << p.setup().host;
  EXPECT_EQ(status, 0) << p.setup().host << ": " << r.outcome << ": " << r.reason;
  EXPECT_EQ(r.outcome, "completed") << p.setup().host << ": " << r.reason;
}

TEST(SplitSecured, TheSecuredSplitRunPlacesTheNeedleAsTheUnsecuredOneAndIsNotOverheard) {
  ASSERT_EQ(std::system(COBRA_MAKE_TEST_PKI " " COBRA_TEST_PKI), 0);
  HostSetup secured_base;
  secured_base.domain = domainFor(0);
  secured_base.dds_security = COBRA_TEST_PKI;
  HostSetup plain_base;
  plain_base.domain = domainFor(1);
  // Both pairs at once: each host's process waits at the meetings for its peer much of the time.
  Pair secured("secured", secured_base);
  Pair plain("plain", plain_base);
  Spy secured_spy(secured_base.domain, "secured_spy"), plain_spy(plain_base.domain, "plain_spy");
  const int statuses[] = {secured.needle.wait(kRunLimit), secured.probe.wait(kRunLimit), plain.needle.wait(kRunLimit),
                          plain.probe.wait(kRunLimit)};
  // Security was on: what crossed the unsecured run was overheard, nothing of the secured one.
  EXPECT_GT(plain_spy.heard(), 0);
  EXPECT_EQ(secured_spy.heard(), 0) << "(-1: the spy never started)";
  expectCompleted(secured.needle, statuses[0]);
  expectCompleted(secured.probe, statuses[1]);
  expectCompleted(plain.needle, statuses[2]);
  expectCompleted(plain.probe, statuses[3]);

  // The same procedure: both charts done, the needle placed as the unsecured run places it, within
  // the tolerance split_procedure_test allows between a split run and one process (the planners
  // have a pace of their own, so two split runs on a loaded machine may differ by a step).
  const HostResult needle = secured.needle.result(), reference = plain.needle.result();
  EXPECT_EQ(needle.final_states.at("needle"), "root.Done");
  EXPECT_EQ(secured.probe.result().final_states.at("us"), "root.Done");
  ASSERT_FALSE(reference.placements.empty());
  ASSERT_EQ(needle.placements.size(), reference.placements.size());
  for (std::size_t i = 0; i < needle.placements.size(); ++i) {
    std::printf("[split] needle %zu placed %.4f mm from its target secured, %.4f mm unsecured\n", i + 1,
                needle.placements[i], reference.placements[i]);
    EXPECT_LE(needle.placements[i], 2.0) << "needle " << i + 1;
    EXPECT_NEAR(needle.placements[i], reference.placements[i], kSplitToleranceMm) << "needle " << i + 1;
  }
  // The secured hosts knew each other by their certificates: no participant refused.
  for (const HostResult* host : {&needle, &reference})
    for (const std::string& line : host->log) EXPECT_EQ(line.find("refused participant"), std::string::npos) << line;
}

}  // namespace
}  // namespace cobra::run::testing
