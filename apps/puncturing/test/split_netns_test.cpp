// The puncturing task split over two hosts that are two network namespaces joined by a veth pair
// (one robot controller in each, as on two computers), as root; skipped with a message otherwise.
// Discovery is unicast (each DdsLink's initial_peers: the other side's address), as between two
// machines whose network does not route multicast. The namespaces are removed even on failure.

#include <gtest/gtest.h>

#include "split_hosts.hpp"

namespace cobra::run::testing {
namespace {

/// Runs `command` (a shell line); returns its exit status.
int sh(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Two namespaces joined by a veth pair: cobra_n<pid> (10.213.N.1/24) and cobra_p<pid>
/// (10.213.N.2/24). Deleting a namespace deletes its end of the pair.
class NamespacePair {
 public:
  NamespacePair() {
    const std::string id = std::to_string(::getpid());
    const std::string subnet = "10.213." + std::to_string(::getpid() % 250) + ".";
    needle = "cobra_n" + id, probe = "cobra_p" + id;
    needle_address = subnet + "1", probe_address = subnet + "2";
    const std::string vn = "vn" + id, vp = "vp" + id;  // interface names: 15 characters at most
    ok_ = sh("ip netns add " + needle) == 0 && sh("ip netns add " + probe) == 0 &&
          sh("ip link add " + vn + " type veth peer name " + vp) == 0 &&
          sh("ip link set " + vn + " netns " + needle) == 0 && sh("ip link set " + vp + " netns " + probe) == 0 &&
          sh("ip -n " + needle + " addr add " + needle_address + "/24 dev " + vn) == 0 &&
          sh("ip -n " + probe + " addr add " + probe_address + "/24 dev " + vp) == 0 &&
          sh("ip -n " + needle + " link set " + vn + " up") == 0 && sh("ip -n " + probe + " link set " + vp + " up") == 0 &&
          sh("ip -n " + needle + " link set lo up") == 0 && sh("ip -n " + probe + " link set lo up") == 0;
  }
  ~NamespacePair() {
    sh("ip netns del " + needle + " 2> /dev/null");
    sh("ip netns del " + probe + " 2> /dev/null");
  }
  NamespacePair(const NamespacePair&) = delete;
  NamespacePair& operator=(const NamespacePair&) = delete;
  bool ok() const { return ok_; }
  /// Bytes received so far by host needle's end of the pair (what crossed the "network").
  long long needleReceivedBytes() const {
    const std::string command = "cat /sys/class/net/vn" + std::to_string(::getpid()) + "/statistics/rx_bytes";
    FILE* out = ::popen(("ip netns exec " + needle + " " + command).c_str(), "r");
    long long bytes = -1;
    if (out != nullptr) {
      if (std::fscanf(out, "%lld", &bytes) != 1) bytes = -1;
      ::pclose(out);
    }
    return bytes;
  }

  std::string needle, probe, needle_address, probe_address;

 private:
  bool ok_ = false;
};

}  // namespace

TEST(SplitProcedureAcrossNamespaces, EachControllerInItsOwnNamespacePlacesTheNeedlesAsOneProcessDoes) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to create network namespaces (ip netns add); run as root";
  if (sh("command -v ip > /dev/null") != 0) GTEST_SKIP() << "no `ip` command (iproute2)";
  const NamespacePair net;
  ASSERT_TRUE(net.ok()) << "could not set up the namespaces and their veth pair";

  const auto folder = std::filesystem::temp_directory_path() / ("cobra_split_netns_" + std::to_string(::getpid()));
  HostSetup single;
  single.folder = folder / "single";
  HostProcess one(single);
  ASSERT_EQ(one.wait(std::chrono::seconds(400)), 0) << one.result().error << one.result().reason;
  const HostResult reference = one.result();

  HostSetup needle, probe;
  needle.host = "needle", probe.host = "probe";
  needle.folder = folder / "needle", probe.folder = folder / "probe";
  needle.domain = probe.domain = 200 + static_cast<int>(::getpid() % 20);  // 200..219
  needle.netns = net.needle, probe.netns = net.probe;
  needle.initial_peers = net.probe_address, probe.initial_peers = net.needle_address;
  HostProcess needle_run(needle), probe_run(probe);
  const int needle_status = needle_run.wait(std::chrono::seconds(400));
  const int probe_status = probe_run.wait(std::chrono::seconds(400));
  const HostResult n = needle_run.result(), p = probe_run.result();
  EXPECT_EQ(needle_status, 0) << n.error << n.outcome << ": " << n.reason;
  EXPECT_EQ(probe_status, 0) << p.error << p.outcome << ": " << p.reason;
  EXPECT_EQ(n.outcome, "completed");
  EXPECT_EQ(p.outcome, "completed");
  ASSERT_EQ(n.placements.size(), reference.placements.size());
  // The samples went through the veth pair (not a shared-memory shortcut between the processes).
  const long long received = net.needleReceivedBytes();
  std::printf("[split netns] host needle's veth end received %.1f MB\n", 1e-6 * static_cast<double>(received));
  EXPECT_GT(received, 1000000);
  for (std::size_t i = 0; i < n.placements.size(); ++i) {
    std::printf("[split netns] needle %zu: %.4f mm (one process: %.4f mm)\n", i + 1, n.placements[i],
                reference.placements[i]);
    EXPECT_NEAR(n.placements[i], reference.placements[i], kSplitToleranceMm) << "needle " << i + 1;
  }
}

}  // namespace cobra::run::testing
