#pragma once
/// @file
/// DdsLink: the one component per process that links it to the other processes of a run over
/// Fast DDS (thesis §4.4): it owns the DDS participant of the "dds" transport, watches
/// the liveliness of the peer processes, and meets them at every instant of a lockstep run
/// (core::ClockSync).
///
/// In a deployment file (package cobra_dds):
/// @code
/// initConfigurator({ "cobra_dds", ... }, { { peer_name = "Link", component_type = "DdsLink" }, ... })
/// -- Link.participant = "needle"; Link.peers = "probe"; Link.lease = 0.1
/// configureComponents({ "Link" })  -- before any connection with transport = "dds"
/// @endcode
///
/// Properties (all read at the first configure; configuring again keeps the participant, cleaning
/// up ends it):
/// - `domain` (int, 0..232): the DDS domain id, as ROS_DOMAIN_ID;
/// - `participant` (text): this process's name, which its peers list (e.g. "needle");
/// - `peers` (text): the participants this process runs with, separated by commas ("probe");
/// - `lease` (s): the liveliness lease: a peer whose liveliness lapses for `lease` (killed, its
///   host unreachable), or that stays silent for `meeting_timeout` at a clock meeting, is lost;
/// - `meeting_timeout` (s, 0: the lease): how long a meeting waits for a peer's announcement
///   while the peer is alive; raise it when an instant of a peer may take longer than the lease
///   (e.g. a planner stepped in the lockstep run);
/// - `join_timeout` (s): how long a meeting waits for a peer never heard of yet (its process
///   starting) before giving it up;
/// - `initial_peers` (text): IPv4 addresses for unicast discovery, separated by commas, when
///   multicast does not reach the other host (e.g. across a veth pair);
/// - `drop_share` (1, 0..1): fault injection, 0 in production: Fast DDS's test UDPv4 transport
///   drops that share of the outgoing data messages (reliable connections retransmit them);
/// - `poll` (s): period at which a writer end's thread sends what ports wrote, i.e. the most
///   latency a wall-clock run adds (a port's write makes no system call); lockstep runs send at
///   the meetings instead;
/// - `lapse_grace` (s, 0: none): a peer whose liveliness lapsed is lost only when it has not come
///   back within this time (a stall of either process past the lease, e.g. at a run's start,
///   is not a loss); a dead peer is then found within lease + lapse_grace;
/// - `udp_only` (bool, default true): UDPv4 only, without Fast DDS's shared memory between the
///   processes of one machine (as between two hosts). false opts into shared memory, at a risk:
///   a peer killed while samples were being sent to it can block the sending threads in the
///   ports' health checks for seconds (its loss found that late), or for good when it died
///   holding a port's interprocess mutex (dds_link_test's killed peer, 1 run in 15 under TSan);
/// - `priority` (0..99): SCHED_FIFO priority of the threads Fast DDS makes for the participant
///   (receiving, liveliness) and of the writer ends' threads; 0: time-sharing. On the wall clock
///   a lease of 0.1 s needs it: a loaded machine delays time-sharing threads past the lease, and
///   the peer is lost while alive. Below the executor's, so that the control loop keeps its time;
/// - `meeting_period` (s, 0..1; 0: every instant): a lockstep run meets only at the instants
///   that are multiples of it, so a sample crosses at the first such instant after it was
///   written: up to one period of delay between processes (as a network adds), in exchange for
///   fewer meetings (each costs a round trip between the processes). Every process of a run must
///   have the same; a peer with another is lost at once, the message naming both periods;
/// - DDS Security (dds/README.md "Security"; DdsTransport::Security; all file paths, all empty
///   by default: no security; a path relative to `security_folder`, which a deployment file sets
///   to its own folder, e.g. `Link.security_folder = here`, else to the working directory):
///   `security_ca` (identity CA certificate, PEM), `security_certificate` (this process's
///   identity, issued by it), `security_key` (its private key), `security_governance` (the
///   signed governance document), `security_permissions` (this process's signed permissions),
///   `security_permissions_ca` (the CA that signed both documents; "" = security_ca). Checked at
///   configure: a missing file, an expired certificate, a key that is not the certificate's,
///   permissions that do not grant the certificate's subject refuse the configure, naming the
///   file and what is wrong. A peer refused by authentication or access control is reported once
///   (stderr, `DdsTransport::problems()`, the event `e_dds_participant_refused`, source: its GUID
///   prefix).
///
/// Output port `events` (every component's; Event, source: the peer's participant name, or the
/// topic; stamped in run time): `e_peer_joined`, `e_peer_lost` (once per peer; never for a peer
/// that said it was done: at a lockstep meeting, or on the wall clock by its farewell when its
/// link was cleaned up after `setDone(true)`, i.e. its run completed; a farewell without it, an
/// error or a safe stop there, loses the peer at once), and the transport's
/// `e_dds_type_mismatch` / `e_dds_incompatible_qos`. They happen on Fast DDS's threads and the
/// clock's thread; those push them into a lock-free queue (256 events) and the link's own step
/// (updateHook) writes them on the port, so the port has one writer, the link's thread, as every
/// port. A link never stepped keeps its events in the queue, and drops (and counts:
/// droppedEvents()) those that find it full.
///
/// Wall clock: give the link an activity of its own (`own_pace = true`, deploy/spec.hpp, with a
/// period, e.g. 1 ms, so that it steps), not a place on the executor's lockstep schedule: stepped
/// by a LockstepClock it would put the transport in lockstep, holding samples for meetings that
/// never come. Its work runs on Fast DDS's threads and its writer ends' anyway.
///
/// Lockstep runs: a DdsLink with peers stepped by a LockstepClock (its activity is a
/// LockstepActivity when it is configured or started) puts the transport in lockstep: writer
/// ends send only when the meeting flushes them and reader ends hold what arrives until the
/// meeting releases it. Set it as the clock's ClockSync (`clock.setClockSync(&link)`): without
/// meetings nothing would travel. (Without peers, a simulated run's dds connections, e.g. to a
/// ROS 2 tool, send as in wall-clock runs.) At `reached(t)` it flushes every
/// writer end, announces {participant, t, done, each writer's last sequence number} on the topic
/// `rt/cobra/link`, waits until every live peer has announced t and every reader end has received
/// from that peer's writers up to the announced sequence numbers (Fast DDS's sample identities:
/// a keep-last history may replace samples, so counts would not do), then releases the held
/// samples up to those numbers into the input ports. A sample written in [t - d, t) is thus read
/// from t on in every process, whichever runs ahead: two runs give the same traces.
/// Peers on one topic with several writers: within one instant their samples come in arrival
/// order.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cobra/core/clock_sync.hpp"
#include "cobra/core/component.hpp"
#include "cobra/dds/dds_transport.hpp"

namespace cobra::dds {

/// See the file's description. One per process (a second one refuses to configure).
class DdsLink final : public core::Component, public core::ClockSync {
 public:
  explicit DdsLink(std::string name);
  ~DdsLink() override;

  void reached(std::chrono::nanoseconds t) noexcept override;
  void setDone(bool done) noexcept override;
  bool peersDone() const noexcept override;
  std::vector<std::string> lostPeers() const override;

  /// The transport whose participant this link made; nullptr unless configured.
  std::shared_ptr<DdsTransport> transport() const;
  /// Events that found the queue to the `events` port full (the link not stepped for 256 events).
  std::uint64_t droppedEvents() const noexcept;

 protected:
  bool configureHook() override;
  bool startHook() override;
  /// Writes the events that foreign threads queued since the last step (allocates nothing).
  void updateHook() override;
  void cleanupHook() override;

 private:
  class Meeting;
  struct ForeignEvents;
  /// Stepped by a LockstepClock, with peers: samples travel only at the clock meetings.
  bool lockstep() const;
  void emit(const std::string& event, const std::string& source);

  core::Property<int> domain_{"domain", 0, "", "DDS domain id (as ROS_DOMAIN_ID)"};
  core::Property<std::string> participant_{"participant", std::string("cobra"), "",
                                           "this process's participant name, which its peers list"};
  core::Property<std::string> peers_{"peers", std::string(), "",
                                     "participant names of the processes this one runs with, comma-separated"};
  core::Property<double> lease_{"lease", 1.0, "s", "liveliness lease: a peer silent this long is lost"};
  core::Property<double> join_timeout_{"join_timeout", 10.0, "s",
                                       "how long a clock meeting waits for a peer never heard of yet"};
  core::Property<double> meeting_timeout_{"meeting_timeout", 0.0, "s",
                                          "how long a clock meeting waits for a live peer's announcement; 0: the lease"};
  core::Property<std::string> initial_peers_{"initial_peers", std::string(), "",
                                             "IPv4 addresses for unicast discovery, comma-separated"};
  core::Property<double> drop_share_{"drop_share", 0.0, "1",
                                     "fault injection: share of outgoing data messages dropped (0 in production)"};
  core::Property<double> poll_{"poll", 1e-4, "s", "period at which writer ends send in wall-clock runs"};
  core::Property<double> lapse_grace_{"lapse_grace", 0.0, "s",
                                      "how long a lapsed peer's liveliness may take to come back before it is lost; 0: lost at once"};
  core::Property<bool> udp_only_{"udp_only", true, "",
                                 "UDPv4 only, without Fast DDS's shared memory between processes of one machine "
                                 "(false: shared memory, which a killed peer can block)"};
  core::Property<int> priority_{"priority", 0, "",
                                "SCHED_FIFO priority 1..99 of the DDS threads (wall clock, short leases); 0: time-sharing"};
  core::Property<double> meeting_period_{
      "meeting_period", 0.0, "s",
      "lockstep: meet at the instants that are multiples of it (samples cross then); 0: at every instant"};
  core::Property<std::string> security_folder_{
      "security_folder", std::string(), "", "folder of relative security_* paths (the deployment file's); \"\": the working directory"};
  core::Property<std::string> security_ca_{"security_ca", std::string(), "", "DDS Security: identity CA certificate (PEM)"};
  core::Property<std::string> security_certificate_{"security_certificate", std::string(), "",
                                                    "DDS Security: this process's identity certificate (PEM)"};
  core::Property<std::string> security_key_{"security_key", std::string(), "", "DDS Security: its private key (PEM)"};
  core::Property<std::string> security_governance_{"security_governance", std::string(), "",
                                                   "DDS Security: governance document, S/MIME-signed by the permissions CA"};
  core::Property<std::string> security_permissions_{"security_permissions", std::string(), "",
                                                    "DDS Security: this process's permissions, S/MIME-signed by the permissions CA"};
  core::Property<std::string> security_permissions_ca_{"security_permissions_ca", std::string(), "",
                                                       "DDS Security: the CA that signed governance and permissions; \"\": security_ca"};
  std::unique_ptr<ForeignEvents> foreign_events_;  // made with the link: events may come until it goes
  std::unique_ptr<Meeting> meeting_;
  std::shared_ptr<DdsTransport> transport_;
};

/// Registers, once per process, the transport "dds" whose participant is the configured
/// DdsLink's: a connection over it made while no DdsLink is configured is refused, naming that.
/// The package cobra_dds calls it when it loads.
void registerLinkedTransport();

}  // namespace cobra::dds
