// DDS Security (DdsTransport::Security, DdsLink's security_* properties): a process with host_a's
// identity and one with host_b's (dds_security_peer) exchange a pose and events with nothing of
// them in clear on the wire, where the same exchange without security shows them; rogue
// participants (no security, another CA, a valid identity without permission, permissions signed
// by another CA) meet host_a first (host_a admits or refuses the participant the rogue says it
// made), then neither command host_a nor read its pose for a watch after the meeting in which the
// same rogue code commands and reads a host without security, and host_a reports each once; bad
// files are refused naming the file and what is wrong. The certificates are the lab's test PKI
// (tools/make_test_pki.sh, made in the build tree). DDS domains 109, 110 and 146..151, this
// test's own.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "cobra/core/activity.hpp"
#include "cobra/core/port.hpp"
#include "cobra/dds/dds_link.hpp"
#include "cobra/test_support/test_support.hpp"
#include "dds_test_support.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;
using Security = DdsTransport::Security;

const std::string kPki = COBRA_TEST_PKI;

/// The test PKI, made once per test process (idempotent: quick when current).
void makePki() {
  static const int status = std::system((std::string(COBRA_MAKE_TEST_PKI) + " " + kPki).c_str());
  ASSERT_EQ(status, 0) << "tools/make_test_pki.sh " << kPki << " failed";
}

std::string pki(const std::string& name) { return kPki + "/" + name; }

Security hostA() {
  return {pki("ca.crt"), pki("host_a.crt"), pki("host_a.key"), pki("governance.p7s"), pki("permissions_host_a.p7s"), ""};
}

std::filesystem::path outputOf(const std::string& role) {
  return std::filesystem::temp_directory_path() / ("cobra_security_peer_" + std::to_string(::getpid()) + "_" + role);
}

/// dds_security_peer in a child process, as `role`, for at most `seconds`; killed and reaped
/// unless waited for.
class Peer : public test::ChildProcess {
 public:
  Peer(int domain, const std::string& role, double seconds)
      : ChildProcess({COBRA_DDS_SECURITY_PEER, std::to_string(domain), kPki, role, outputOf(role).string(),
                      std::to_string(seconds)}),
        out_(outputOf(role)) {}
  /// The value of its output line `key` ("guid", "reader", "writer", "wrote", "read", "end").
  std::string said(const std::string& key) const {
    std::ifstream in(out_);
    for (std::string line; std::getline(in, line);)
      if (line.rfind(key + " ", 0) == 0) return line.substr(key.size() + 1);
    return "(no line '" + key + "')";
  }

 private:
  std::filesystem::path out_;
};

/// A DdsTransport with `options` registered as "dds_sec" for the life of the object.
struct Registered {
  explicit Registered(const DdsTransport::Options& options) : transport(registerDdsTransport(options, "dds_sec")) {}
  ~Registered() { core::TransportRegistry::remove("dds_sec"); }
  Registered(const Registered&) = delete;
  Registered& operator=(const Registered&) = delete;
  core::ConnPolicy policy(const std::string& topic, core::ConnPolicy base = core::ConnPolicy::data()) const {
    base.transport = "dds_sec";
    base.topic = topic;
    return base;
  }
  std::shared_ptr<DdsTransport> transport;
};

core::ConnPolicy eventPolicy() {
  core::ConnPolicy events = core::ConnPolicy::buffer(16);
  events.options = {{"reliability", "reliable"}, {"depth", "16"}};
  return events;
}

/// Every RTPS message a participant sends, as it goes on the wire.
struct WireTap {
  std::mutex mutex;
  std::vector<std::string> messages;
  std::function<void(const unsigned char*, std::size_t)> tap() {
    return [this](const unsigned char* data, std::size_t size) {
      std::lock_guard lock(mutex);
      messages.emplace_back(reinterpret_cast<const char*>(data), size);
    };
  }
  /// How many messages contain `bytes`.
  int containing(const std::string& bytes) {
    std::lock_guard lock(mutex);
    return static_cast<int>(std::count_if(messages.begin(), messages.end(),
                                          [&](const std::string& m) { return m.find(bytes) != std::string::npos; }));
  }
  std::size_t size() {
    std::lock_guard lock(mutex);
    return messages.size();
  }
};

std::string bytesOf(double value) { return std::string(reinterpret_cast<const char*>(&value), sizeof value); }

/// A pose and events from host_a (this process) to host_b (a peer process, `role`) and back,
/// every message this process sent kept in `wire`.
void exchange(int domain, const std::string& role, const Security& security, WireTap& wire) {
  Peer peer(domain, role, 30.0);
  DdsTransport::Options options{domain, "cobra_host_a", false};
  options.security = security;
  options.wire_tap = wire.tap();
  Registered dds(options);
  core::OutputPort<KDL::Frame> pose_out("pose_out", "", "m");
  core::InputPort<KDL::Frame> pose_in("pose_in", "", "m");
  core::OutputPort<core::Event> events_out("events_out", "", "");
  core::InputPort<core::Event> events_in("events_in", "", "");
  const core::ConnPolicy events = eventPolicy();
  core::connectToTransport(pose_out, dds.policy("ISUR/measCartPose"));
  core::connectToTransport(pose_in, dds.policy("UR5/measCartPose"));
  core::connectToTransport(events_out, dds.policy("NeedleTaskSup/outputEvents", events));
  core::connectToTransport(events_in, dds.policy("ProbeTaskSup/outputEvents", events));
  for (const char* topic : {"ISUR/measCartPose", "UR5/measCartPose", "NeedleTaskSup/outputEvents", "ProbeTaskSup/outputEvents"})
    ASSERT_TRUE(dds.transport->waitForMatch(topic, 20s)) << topic;

  const KDL::Frame frame(KDL::Rotation::RotZ(0.5), KDL::Vector(0.123456789, -0.987654321, 0.314159265));
  KDL::Frame echoed;
  ASSERT_TRUE(test::pollUntil([&] {
    pose_out.write(frame);
    return pose_in.read(echoed) == core::FlowStatus::NewData;
  }, 10s));
  EXPECT_TRUE(KDL::Equal(echoed, KDL::Frame(frame.M, frame.p + KDL::Vector(1.0, 0, 0)), 1e-12));
  events_out.write(test::event("e_needle_inserted"));
  core::Event answer;
  ASSERT_TRUE(test::pollUntil([&] { return events_in.read(answer) == core::FlowStatus::NewData; }, 10s));
  EXPECT_EQ(answer.name.str(), "ack_e_needle_inserted");
  events_out.write(test::event("quit"));
  EXPECT_EQ(peer.wait(10s), 0);
  EXPECT_EQ(dds.transport->problems(), std::vector<std::string>{});
}

TEST(DdsSecurity, TwoProcessesWithValidIdentitiesExchangeDataWithNothingInClearOnTheWire) {
  makePki();
  WireTap wire;
  exchange(146, "host_b", hostA(), wire);
  ASSERT_GT(wire.size(), 10u);
  // The pose's coordinates (CDR: the doubles' bytes), the event's name, the topic (discovery).
  EXPECT_EQ(wire.containing(bytesOf(0.123456789)), 0);
  EXPECT_EQ(wire.containing("e_needle_inserted"), 0);
  EXPECT_EQ(wire.containing("ISUR/measCartPose"), 0);
}

// The control: the same tap sees the exchange in clear without security.
TEST(DdsSecurity, WithoutSecurityTheSameExchangeIsInClearOnTheWire) {
  makePki();
  WireTap wire;
  exchange(147, "plain_b", {}, wire);
  EXPECT_GT(wire.containing(bytesOf(0.123456789)), 0);
  EXPECT_GT(wire.containing("e_needle_inserted"), 0);
  EXPECT_GT(wire.containing("ISUR/measCartPose"), 0);
}

/// How long a rogue is watched once host_a met it (admitted or refused its participant): the
/// same rogue against a host without security gets a command through and reads a pose within it
/// (TheSameRogueCommandsAndReadsAnUnsecuredHostWithinTheWatch), so silence this long after the
/// meeting is a refusal, not a match still to come.
constexpr auto kWatch = 2s;

std::string statusText(DdsTransport::RemoteParticipant::Status status) {
  using Status = DdsTransport::RemoteParticipant::Status;
  return status == Status::Admitted ? "admitted" : status == Status::Refused ? "refused" : "discovered";
}

/// What became of a rogue (dds_security_peer `role`) beside host_a.
struct RogueRun {
  /// host_a's view of the rogue's participant once admitted or refused; none: they never met.
  std::optional<DdsTransport::RemoteParticipant> met;
  std::string rogue_guid;  ///< the GUID prefix the rogue says its participant has
  int commanded = 0;       ///< the rogue's commands host_a read, from its start to the watch's end
  double first_command = -1.0;  ///< s after the meeting; -1: none
  int exit_status = -1;         ///< the rogue's, after SIGTERM at the watch's end
  std::vector<std::string> problems;  ///< host_a's
};

/// host_a (`security`; none: without) publishes its measured pose and listens to host probe's
/// chart commands, while the rogue, started beside it, reads the one and writes the other every
/// 10 ms. Once host_a met the rogue's participant (waitForParticipant: discovery's and
/// authentication's callbacks), host_a keeps publishing and listening for kWatch; then the rogue
/// is ended (SIGTERM: it was reading and writing until then).
RogueRun runRogue(int domain, const std::string& role, Peer& rogue, const Security& security) {
  DdsTransport::Options options{domain, "cobra_host_a", false};
  options.security = security;
  Registered dds(options);
  core::OutputPort<KDL::Frame> pose_out("pose_out", "", "m");
  core::InputPort<core::Event> commands("commands", "", "");
  core::connectToTransport(pose_out, dds.policy("ISUR/measCartPose"));
  core::connectToTransport(commands, dds.policy("ProbeTaskSup/outputEvents", eventPolicy()));
  RogueRun run;
  const auto start = std::chrono::steady_clock::now();
  const auto read_commands = [&](std::chrono::steady_clock::time_point met_at) {
    core::Event e;
    while (commands.read(e) == core::FlowStatus::NewData) {
      if (e.name != "e_rogue_command") continue;
      if (run.commanded++ == 0)
        run.first_command = std::chrono::duration<double>(std::chrono::steady_clock::now() - met_at).count();
    }
  };
  run.met = dds.transport->waitForParticipant("cobra_" + role, 20s);
  if (run.met) {
    const auto met_at = std::chrono::steady_clock::now();
    std::printf("[%s] host_a met the rogue %.3f s after host_a was made: %s\n", role.c_str(),
                std::chrono::duration<double>(met_at - start).count(), statusText(run.met->status).c_str());
    // Its first line, written as soon as its participant exists (it may be met a moment before).
    test::pollUntil([&] { return rogue.said("guid").rfind("(no line", 0) != 0; }, 5s);
    run.rogue_guid = rogue.said("guid");
    while (std::chrono::steady_clock::now() < met_at + kWatch) {
      pose_out.write(KDL::Frame(KDL::Vector(0.1, 0.2, 0.3)));
      read_commands(met_at);
      std::this_thread::sleep_for(10ms);  // the rogue's own pace
    }
    read_commands(met_at);
  }
  rogue.terminate();
  run.exit_status = rogue.wait(10s);
  run.problems = dds.transport->problems();
  for (const std::string& p : run.problems) std::printf("[%s] %s\n", role.c_str(), p.c_str());
  return run;
}

// The control: the same rogue against a host without security (domain 109) commands it and reads
// its pose within kWatch of their meeting. The rogue tests' silence is the security's doing, not
// a rogue that cannot talk or a watch too short to see it.
TEST(DdsSecurity, TheSameRogueCommandsAndReadsAnUnsecuredHostWithinTheWatch) {
  makePki();
  Peer rogue(109, "unsecured", 60.0);  // until runRogue ends it
  const RogueRun run = runRogue(109, "unsecured", rogue, {});
  ASSERT_TRUE(run.met) << "host_a never met the rogue";
  EXPECT_EQ(statusText(run.met->status), "admitted");
  EXPECT_EQ(run.met->guid_prefix, run.rogue_guid);
  EXPECT_EQ(run.met->subject, "") << "no certificate";
  EXPECT_EQ(run.exit_status, 0);
  EXPECT_EQ(rogue.said("end"), "terminated") << "it was reading and writing all through the watch";
  EXPECT_GT(run.commanded, 0);
  EXPECT_GT(std::atoi(rogue.said("read").c_str()), 0) << rogue.said("read");
  std::printf("[unsecured host] first command %.3f s after the meeting; %d commands, %s poses read\n",
              run.first_command, run.commanded, rogue.said("read").c_str());
  EXPECT_EQ(run.problems, std::vector<std::string>{});
}

// host_a with its identity; each rogue meets it first (host_a admits or refuses the participant
// the rogue made, named by its GUID prefix), then neither commands it nor reads its pose for
// kWatch, and host_a reports it once.
struct RogueCase {
  std::string role;
  int domain;
  std::string reported;  ///< host_a's report after the rogue's GUID prefix; "": admitted, none
};
void PrintTo(const RogueCase& c, std::ostream* out) { *out << c.role; }
class Rogue : public ::testing::TestWithParam<RogueCase> {};

TEST_P(Rogue, MeetsTheHostThenNeitherCommandsNorReadsAPoseAndIsReportedOnce) {
  makePki();
  const RogueCase& c = GetParam();
  Peer rogue(c.domain, c.role, 60.0);  // until runRogue ends it
  const RogueRun run = runRogue(c.domain, c.role, rogue, hostA());
  ASSERT_TRUE(run.met) << c.role << ": host_a never met the rogue: its silence would prove nothing";
  ASSERT_EQ(run.met->guid_prefix, run.rogue_guid) << c.role << ": host_a met another participant than the rogue's";
  EXPECT_EQ(run.exit_status, 0) << c.role;
  EXPECT_EQ(rogue.said("end"), "terminated") << c.role << ": it was reading and writing all through the watch";
  EXPECT_GE(std::atoi(rogue.said("wrote").c_str()), 1) << c.role;
  EXPECT_EQ(run.commanded, 0) << c.role;
  EXPECT_EQ(rogue.said("read"), "0") << c.role;
  const std::string head = "dds participant 'cobra_host_a' refused participant ";
  std::vector<std::string> refused;
  for (const std::string& p : run.problems)
    if (p.find("refused participant") != std::string::npos) refused.push_back(p);
  if (c.role == "no_permission") {
    // Authenticated (a certificate of host_a's CA) and granted the domain: admitted. Its own
    // participant refuses the endpoints its permissions do not grant: nothing of it reaches host_a.
    EXPECT_EQ(statusText(run.met->status), "admitted");
    EXPECT_EQ(run.met->subject, "/C=CH/O=cobra lab/CN=cobra noperm") << "its identity token's";
    EXPECT_EQ(refused, std::vector<std::string>{});
    EXPECT_EQ(rogue.said("writer"),
              "cannot connect events_out (Event) to dds topic 'ProbeTaskSup/outputEvents': dds: Fast DDS refused the writer of topic 'rt/ProbeTaskSup/outputEvents' with QoS reliable, volatile, "
              "depth 16, lease infinite: with DDS Security, participant 'cobra_no_permission' "
              "('CN=cobra noperm,O=cobra lab,C=CH') may publish only what its permissions '" + pki("permissions_noperm.p7s") +
              "' grant, and they do not grant publish on 'rt/ProbeTaskSup/outputEvents'");
    EXPECT_EQ(rogue.said("reader"),
              "cannot connect pose_in (KDL.Frame) to dds topic 'ISUR/measCartPose': dds: Fast DDS refused the reader of topic 'rt/ISUR/measCartPose' with QoS reliable, volatile, depth 1, "
              "lease infinite: with DDS Security, participant 'cobra_no_permission' ('CN=cobra noperm,O=cobra lab,C=CH') "
              "may subscribe only what its permissions '" + pki("permissions_noperm.p7s") +
              "' grant, and they do not grant subscribe on 'rt/ISUR/measCartPose'");
    return;
  }
  EXPECT_EQ(statusText(run.met->status), "refused") << c.role;
  EXPECT_EQ(rogue.said("writer"), "ok") << c.role;
  EXPECT_EQ(rogue.said("reader"), "ok") << c.role;
  // Once, naming it: its GUID prefix, its name and (secured) its certificate, and why.
  ASSERT_EQ(refused.size(), 1u) << c.role;
  EXPECT_EQ(refused[0], head + run.rogue_guid + c.reported);
}

INSTANTIATE_TEST_SUITE_P(DdsSecurity, Rogue,
                         ::testing::Values(
                             RogueCase{"unsecured", 148,
                                       " 'cobra_unsecured': it failed DDS Security's authentication (no certificate of "
                                       "this participant's identity CA, or none at all); nothing it sends is read, "
                                       "nothing is sent to it"},
                             RogueCase{"other_ca", 149,
                                       " 'cobra_other_ca' (certificate '/C=CH/O=cobra lab/CN=cobra host_b'): it failed DDS "
                                       "Security's authentication (no certificate of this participant's identity CA, or "
                                       "none at all); nothing it sends is read, nothing is sent to it"},
                             RogueCase{"no_permission", 150, ""},
                             RogueCase{"forged_permissions", 151,
                                       " 'cobra_forged_permissions' (certificate '/C=CH/O=cobra lab/CN=cobra noperm'): its "
                                       "permissions were refused (Remote participant PermissionsCA differs from local); "
                                       "nothing it sends is read, nothing is sent to it"}),
                         [](const auto& param_info) { return param_info.param.role; });

/// The message of making a participant with `security` (domain 146: none is made).
std::string refusal(const Security& security) {
  return test_support::messageOf([&] {
    DdsTransport::Options options{146, "needle", false};
    options.security = security;
    DdsTransport dds(options);
  });
}

TEST(DdsSecurity, BadFilesAreRefusedNamingTheFileAndWhatIsWrong) {
  makePki();
  Security s = hostA();
  s.certificate = pki("missing.crt");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_certificate '" + pki("missing.crt") + "': no such file");
  s = hostA();
  s.certificate = pki("expired.crt");
  s.key = pki("expired.key");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_certificate '" + pki("expired.crt") +
                            "': the certificate 'CN=cobra expired,O=cobra lab,C=CH' expired on Jan  1 00:00:00 2021 GMT; "
                            "make it again (tools/make_test_pki.sh for a lab's test certificates)");
  s = hostA();
  s.permissions = pki("permissions_host_b.p7s");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_permissions '" + pki("permissions_host_b.p7s") +
                            "': grants nothing to the certificate '" + pki("host_a.crt") +
                            "' (subject 'CN=cobra host_a,O=cobra lab,C=CH'): its grants are for 'CN=cobra host_b,O=cobra "
                            "lab,C=CH'; use the permissions of this certificate's subject");
  s = hostA();
  s.certificate = pki("rogue.crt");
  s.key = pki("rogue.key");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_certificate '" + pki("rogue.crt") +
                            "': the certificate 'CN=cobra host_b,O=cobra lab,C=CH' (issued by 'CN=rogue CA,O=rogue "
                            "lab,C=CH') does not verify with the identity CA '" + pki("ca.crt") +
                            "' (unable to get local issuer certificate)");
  s = hostA();
  s.key = pki("host_b.key");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_key '" + pki("host_b.key") + "': is not the key of the certificate '" +
                            pki("host_a.crt") + "' ('CN=cobra host_a,O=cobra lab,C=CH')");
  s = hostA();
  s.governance = pki("rogue_governance.p7s");
  EXPECT_EQ(refusal(s).rfind("dds participant 'needle': security_governance '" + pki("rogue_governance.p7s") +
                                 "': its signature does not verify with the permissions CA '" + pki("ca.crt") + "' (",
                             0),
            0u)
      << refusal(s);
  s = hostA();
  s.governance = pki("ca.crt");
  EXPECT_EQ(refusal(s).rfind("dds participant 'needle': security_governance '" + pki("ca.crt") +
                                 "': is not an S/MIME signed document (",
                             0),
            0u)
      << refusal(s);
  s = hostA();
  s.governance = pki("broken_governance.p7s");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_governance '" + pki("broken_governance.p7s") +
                            "': is signed but is not well-formed XML (line 4: XML_ERROR_MISMATCHED_ELEMENT, XMLElement "
                            "name=domain_rule): correct the XML document and sign it again");
  s = hostA();
  s.governance = pki("permissions_host_a.p7s");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_governance '" + pki("permissions_host_a.p7s") +
                            "': is signed but is no governance document (no <domain_access_rules>)");
  s = hostA();
  s.governance = pki("missing_governance.p7s");
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_governance '" + pki("missing_governance.p7s") +
                            "': no such file");
  s = hostA();
  s.key.clear();
  EXPECT_EQ(refusal(s), "dds participant 'needle': security_key is not given: DDS Security needs security_ca, "
                        "security_certificate, security_key, security_governance and security_permissions "
                        "(security_permissions_ca: security_ca when not given), or none of them");
}

// DdsLink's properties: relative paths from security_folder, checked at configure; a refused
// participant comes on the link's events port, from the link's own step, once while the rogue
// keeps on for kWatch after (domain 110).
TEST(DdsSecurity, ALinksRelativeFilesComeFromItsSecurityFolderAndARefusedPeerIsItsEvent) {
  makePki();
  DdsLink link("Link");
  const auto set = [&](const std::string& name, const std::string& value) { link.property(name).setFromText(value); };
  set("domain", "110");
  set("participant", "needle");
  set("security_folder", kPki);
  set("security_ca", "ca.crt");
  set("security_certificate", "host_a.crt");
  set("security_key", "host_a.key");
  set("security_governance", "governance.p7s");
  set("security_permissions", "permissions_host_b.p7s");
  EXPECT_EQ(link.configure().message,
            "component 'Link': dds participant 'needle': security_permissions '" + pki("permissions_host_b.p7s") +
                "': grants nothing to the certificate '" + pki("host_a.crt") +
                "' (subject 'CN=cobra host_a,O=cobra lab,C=CH'): its grants are for 'CN=cobra host_b,O=cobra lab,C=CH'; "
                "use the permissions of this certificate's subject");
  set("security_permissions", "permissions_host_a.p7s");
  ASSERT_TRUE(link.configure()) << link.configure().message;
  core::InputPort<core::Event> events("events", "", "");
  core::connectPorts(link.events(), events, core::ConnPolicy::buffer(16));
  ASSERT_TRUE(link.start());
  Peer rogue(110, "unsecured", 60.0);  // until terminated below
  std::vector<std::string> refused;  // their sources
  const auto step = [&] {
    static_cast<core::SlaveActivity&>(link.activity()).step();  // the test's thread is the link's
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData)
      if (e.name == "e_dds_participant_refused") refused.push_back(e.source.str());
  };
  // The meeting: the link's event, from its step, once its participant refused the rogue's.
  ASSERT_TRUE(test::pollUntil([&] {
    step();
    return !refused.empty();
  }, 20s)) << "the link never met the rogue";
  // Then once only, while the rogue keeps writing for kWatch.
  const auto met_at = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < met_at + kWatch) {
    step();
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0], rogue.said("guid")) << "the source: the refused participant's GUID prefix";
  const auto met = link.transport()->waitForParticipant("cobra_unsecured", 0s);
  ASSERT_TRUE(met);
  EXPECT_EQ(statusText(met->status), "refused");
  EXPECT_EQ(met->guid_prefix, refused[0]);
  rogue.terminate();
  EXPECT_EQ(rogue.wait(5s), 0);
  EXPECT_EQ(rogue.said("end"), "terminated") << "it was writing all through the watch";
  EXPECT_EQ(rogue.said("read"), "0");
  EXPECT_TRUE(link.stop());
  EXPECT_TRUE(link.cleanup());
}

}  // namespace
}  // namespace cobra::dds
