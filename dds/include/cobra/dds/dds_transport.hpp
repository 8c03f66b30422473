#pragma once
/// @file
/// The "dds" transport: a connection whose samples travel over Fast DDS, one topic per
/// connection, so that its two ends may be in different processes or hosts, and a ROS 2 node can
/// subscribe to (or publish on) it.
///
/// In a deployment file:
/// @code
/// conn_policy = { type = "buffer", size = 16, transport = "dds", topic = "needle/events",
///                 qos = { reliability = "reliable", depth = 16, lease = 0.1 } }
/// @endcode
/// - `topic`: a ROS 2 name ("needle/pose", a leading '/' allowed); the DDS topic is "rt/" + it, as
///   ROS 2 names it. The DDS type is the port type's wire (codec.hpp: a ROS 2 message for
///   cobra's built-in types, a record's own); the type must be registered (register_type.hpp).
/// - `qos.reliability`: "reliable" (default) or "best_effort"; `qos.depth`: samples DDS keeps
///   per topic for a late or slow reader (default: the connection's size); `qos.lease`: the
///   liveliness lease in s (default: infinite); `qos.durability`: "volatile" (default) or
///   "transient_local" (a late reader gets the last `depth` samples).
/// Each end keeps the semantics of the connection's type: `data` (latest value) or `buffer(n)` /
/// `circular(n)` (FIFO of n) between the port and the transport, and the flow status of reads.
///
/// The real-time side never waits on DDS: a port's write pushes into the lock-free channel of the
/// writer's end (preallocated like any connection) and sets a flag, with no system call; the end's
/// own thread looks at the flag every `Options::poll`, takes the samples, converts and publishes
/// them. In a deployment, the transport "dds" is the DdsLink component's (dds_link.hpp), which
/// also meets the other processes of a lockstep run. On the reader's side, Fast DDS's listener thread
/// converts each sample and writes it into the channel the input port reads.
///
/// Problems DDS reports or that discovery shows (a topic whose two ends have different types, a
/// QoS the two ends cannot agree on) are logged to stderr, kept (`problems()`) and sent as an
/// event on `events()` (`e_dds_type_mismatch`, `e_dds_incompatible_qos`, source: the topic), each
/// naming the topic and both ends' types or QoS.

#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/port.hpp"
#include "cobra/core/transport.hpp"

namespace cobra::dds {

namespace detail {
class Participant;
}

/// One DDS domain participant and the connections it carries. Thread-safe.
class DdsTransport final : public core::Transport {
 public:
  /// DDS Security (OMG DDS-Security 1.1, Fast DDS's built-in plugins): PKI-DH authentication,
  /// Access-Permissions access control, AES-GCM-GMAC encryption. Files are PEM certificates and
  /// keys and S/MIME-signed XML documents (dds/README.md "Security"; tools/make_test_pki.sh makes a
  /// lab's). All empty: no security. Otherwise every file but `permissions_ca` must be given;
  /// each is checked when the participant is made (readable, parsed, the certificate valid now
  /// and issued by `ca`, the key the certificate's, both documents signed by `permissions_ca`,
  /// the permissions granting the certificate's subject): a problem throws core::Error naming the
  /// file and what is wrong.
  struct Security {
    std::string ca;              ///< identity CA certificate (PEM): the peers' certificates must be issued by it
    std::string certificate;     ///< this participant's identity certificate (PEM), issued by `ca`
    std::string key;             ///< its private key (PEM, unencrypted)
    std::string governance;      ///< the domain governance document, signed (S/MIME) by `permissions_ca`
    std::string permissions;     ///< this participant's permissions document, signed by `permissions_ca`
    std::string permissions_ca;  ///< the CA that signed the two documents; "" = `ca`
    /// True when any file is given.
    bool enabled() const {
      return !ca.empty() || !certificate.empty() || !key.empty() || !governance.empty() || !permissions.empty() ||
             !permissions_ca.empty();
    }
  };

  struct Options {
    int domain = 0;                    ///< DDS domain id (0..232), as ROS_DOMAIN_ID
    std::string participant = "cobra";  ///< the participant's name, seen by discovery tools
    bool log = true;                   ///< also print problems on stderr
    /// IPv4 addresses of hosts to discover by unicast (when multicast is not routed, e.g. across
    /// a veth pair); empty: multicast discovery only.
    std::vector<std::string> initial_peers = {};
    /// Fault injection: the share (0..1) of outgoing data messages that Fast DDS's test UDPv4
    /// transport drops (then the participant uses UDPv4 only). 0: Fast DDS's own transports.
    double drop_share = 0.0;
    /// UDPv4 only, without Fast DDS's shared-memory transport between processes of one host: the
    /// network path, e.g. between network namespaces of one host as between two hosts. (Fast
    /// DDS's data sharing is off for every participant: participant.cpp says why.)
    bool udp_only = false;
    /// Period (s) at which a writer end's thread looks for samples to send: the latency a
    /// wall-clock run adds to each sample, at most. A port's write only pushes and sets a flag;
    /// it makes no system call.
    double poll = 1e-4;
    /// SCHED_FIFO priority (1..99) of the threads Fast DDS makes for the participant (receiving,
    /// liveliness, resending) and of the writer ends' threads; 0: they run as the thread that
    /// makes them (time-sharing, usually). On the wall clock a short liveliness lease needs it:
    /// a loaded machine delays time-sharing threads past the lease. When refused (no
    /// CAP_SYS_NICE), the threads run time-sharing and stderr says so.
    int priority = 0;
    /// DDS Security; default: none (see Security).
    Security security = {};
    /// Tests only: called with every RTPS message this participant sends over UDPv4 (as it goes
    /// on the wire: encrypted with security), on Fast DDS's sending threads. Set, the participant
    /// uses UDPv4 only (Fast DDS's test transport, which drops nothing unless `drop_share`).
    std::function<void(const unsigned char* data, std::size_t size)> wire_tap = {};
  };

  explicit DdsTransport(Options options);
  ~DdsTransport() override;
  DdsTransport(const DdsTransport&) = delete;
  DdsTransport& operator=(const DdsTransport&) = delete;

  void check(const core::ConnPolicy& policy) const override;
  void makeWriterEnd(core::OutputPortBase& output, const core::ConnPolicy& policy, core::PortBase* peer) override;
  void makeReaderEnd(core::InputPortBase& input, const core::ConnPolicy& policy, core::PortBase* peer) override;

  /// Problem events (`e_dds_type_mismatch`, `e_dds_incompatible_qos`, source: the topic; with
  /// DDS Security `e_dds_participant_refused`, source: the refused participant's GUID prefix);
  /// connect it like any output port, e.g. to a supervisor's inputEvents with a buffer policy.
  core::OutputPort<core::Event>& events();
  /// Every problem reported so far, as its full message.
  std::vector<std::string> problems() const;
  /// Waits until every end on `topic` (the ROS 2 name, as in the policy) in this participant is
  /// matched with at least one end of the other side; false after `timeout`.
  bool waitForMatch(const std::string& topic, std::chrono::milliseconds timeout) const;

  /// A remote participant that discovery announced to this one.
  struct RemoteParticipant {
    enum class Status {
      Discovered,  ///< announced; with DDS Security, its authentication is not over yet
      Admitted,    ///< met: without DDS Security, at discovery; with it, authenticated and granted the domain
      Refused,     ///< with DDS Security: refused (e_dds_participant_refused); nothing crosses
    };
    std::string guid_prefix;  ///< "01.0f.78.fd.e1.70.99.80.00.00.00.00", as the reports name it
    std::string name;         ///< its participant name ("" until discovery said it)
    /// Its certificate's subject as its identity token says it ("/C=CH/O=lab/CN=x"); "" without.
    std::string subject;
    Status status = Status::Discovered;
  };
  /// Every remote participant announced since this one was made (one that left stays, with its
  /// last status): that two hosts did find each other, and what became of a stranger.
  std::vector<RemoteParticipant> participants() const;
  /// Waits (on discovery's and authentication's callbacks, no polling) until a remote participant
  /// named `name` is admitted or refused, and returns it; nothing after `timeout`.
  std::optional<RemoteParticipant> waitForParticipant(const std::string& name, std::chrono::milliseconds timeout) const;
  /// This participant's GUID prefix ("01.0f.78.fd.e1.70.99.80.00.00.00.00"), as its peers' reports
  /// and participants() name it.
  std::string guidPrefix() const;
  /// The DDS topic of a connection's `topic`: "rt/needle/pose" for "needle/pose" or "/needle/pose".
  static std::string ddsTopic(const std::string& topic);

 private:
  friend class DdsLink;  // its clock meetings and liveliness use the participant
  std::shared_ptr<detail::Participant> participant_;
};

/// Registers a DdsTransport as `name` ("dds") in core's TransportRegistry, so that connection
/// policies with `transport = "dds"` use it. Registering again from the same owner replaces it.
/// @return the registered transport (e.g. to connect its events()).
std::shared_ptr<DdsTransport> registerDdsTransport(DdsTransport::Options options = {}, const std::string& name = "dds");

}  // namespace cobra::dds
