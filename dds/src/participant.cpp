#include "cobra/dds/detail/participant.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/rtps/builtin/data/ParticipantProxyData.h>
#include <fastdds/rtps/builtin/data/ReaderProxyData.h>
#include <fastdds/rtps/builtin/data/WriterProxyData.h>
#include <fastdds/rtps/participant/ParticipantDiscoveryInfo.h>
#include <fastdds/rtps/reader/ReaderDiscoveryInfo.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/test_UDPv4TransportDescriptor.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>
#include <fastrtps/utils/IPLocator.h>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>

#include "cobra/core/error.hpp"
#include "cobra/text/number.hpp"
#include "security.hpp"

namespace cobra::dds::detail {
namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

/// While alive, the calling thread runs SCHED_FIFO at `priority` (0: unchanged), so that the
/// threads it creates inherit it (glibc's default, PTHREAD_INHERIT_SCHED, and std::thread's);
/// its own scheduling comes back after.
class FifoWhileCreating {
 public:
  FifoWhileCreating(int priority, const std::string& participant) {
    if (priority == 0 || pthread_getschedparam(pthread_self(), &policy_, &old_) != 0) return;
    raised_ = setFifo(priority, participant);
  }
  ~FifoWhileCreating() {
    if (raised_) pthread_setschedparam(pthread_self(), policy_, &old_);
  }
  FifoWhileCreating(const FifoWhileCreating&) = delete;
  FifoWhileCreating& operator=(const FifoWhileCreating&) = delete;

  /// The calling thread to SCHED_FIFO `priority`; false (said once on stderr) when refused.
  static bool setFifo(int priority, const std::string& participant) noexcept {
    sched_param p{};
    p.sched_priority = priority;
    const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
    if (error == 0) return true;
    static std::once_flag said;
    std::call_once(said, [&] {
      std::cerr << "cobra dds: participant '" << participant << "': SCHED_FIFO priority " << priority << " refused ("
                << std::strerror(error) << "): its threads run time-sharing\n";
    });
    return false;
  }

 private:
  int policy_ = SCHED_OTHER;
  sched_param old_{};
  bool raised_ = false;
};

std::string text(const rtps::GUID_t& guid) {
  std::ostringstream out;
  out << guid;
  return out.str();
}

std::string text(const rtps::GuidPrefix_t& prefix) {
  std::ostringstream out;
  out << prefix;
  return out.str();
}

double seconds(const eprosima::fastrtps::Duration_t& duration) {
  if (duration == eprosima::fastrtps::c_TimeInfinite) return 0.0;
  return static_cast<double>(duration.to_ns()) * 1e-9;
}

template <class Qos>
EndpointQos qosOf(const Qos& qos) {
  EndpointQos out;
  out.reliable = qos.m_reliability.kind == fdds::RELIABLE_RELIABILITY_QOS;
  out.transient_local = qos.m_durability.kind != fdds::VOLATILE_DURABILITY_QOS;
  out.lease = seconds(qos.m_liveliness.lease_duration);
  out.depth = 0;  // not announced by discovery
  return out;
}

/// Why a writer offering `w` and a reader requesting `r` cannot match, or "" when they can.
std::string incompatibility(const EndpointQos& w, const EndpointQos& r) {
  if (r.reliable && !w.reliable) return "reliability";
  if (r.transient_local && !w.transient_local) return "durability";
  if (r.lease > 0.0 && (w.lease == 0.0 || w.lease > r.lease)) return "lease";
  return "";
}

const char* policyName(std::uint32_t id) {
  switch (id) {
    case fdds::DURABILITY_QOS_POLICY_ID: return "durability";
    case fdds::DEADLINE_QOS_POLICY_ID: return "deadline";
    case fdds::OWNERSHIP_QOS_POLICY_ID: return "ownership";
    case fdds::LIVELINESS_QOS_POLICY_ID: return "liveliness lease";
    case fdds::RELIABILITY_QOS_POLICY_ID: return "reliability";
    case fdds::DESTINATIONORDER_QOS_POLICY_ID: return "destination order";
    case fdds::PRESENTATION_QOS_POLICY_ID: return "presentation";
    case fdds::DATAREPRESENTATION_QOS_POLICY_ID: return "data representation";
    default: return "a QoS policy";
  }
}

std::string describeLocal(const EndpointInfo& e) {
  return std::string(e.writer ? "the writer of " : "the reader of ") + e.port + " (" + e.cobra_type + ") in this process";
}

/// A millisecond duration in Fast DDS's type.
eprosima::fastrtps::Duration_t milliseconds(std::uint32_t ms) { return eprosima::fastrtps::Duration_t(0, ms * 1000000U); }

template <class Qos>
void applyQos(Qos& qos, const EndpointQos& wanted) {
  qos.reliability().kind = wanted.reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  qos.durability().kind = wanted.transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = wanted.depth;
  qos.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
  if (wanted.lease > 0.0) {
    qos.liveliness().lease_duration = eprosima::fastrtps::Duration_t(static_cast<long double>(wanted.lease));
    // Fast DDS asserts liveliness at this period; it must be below the lease.
    qos.liveliness().announcement_period = eprosima::fastrtps::Duration_t(static_cast<long double>(wanted.lease) / 3);
  }
}

}  // namespace

std::string EndpointQos::describe(bool with_depth) const {
  std::string out = std::string(reliable ? "reliable" : "best_effort") + ", " + (transient_local ? "transient_local" : "volatile");
  if (with_depth) out += ", depth " + std::to_string(depth);
  out += ", lease " + (lease > 0.0 ? text::number(lease) + " s" : std::string("infinite"));
  return out;
}

Participant::Participant(const DdsTransport::Options& options)
    : poll_(std::chrono::nanoseconds(static_cast<std::int64_t>(options.poll * 1e9))),
      priority_(options.priority),
      name_(options.participant),
      log_(options.log) {
  const int domain = options.domain;
  const std::string& name = options.participant;
  if (!(options.poll > 0.0 && options.poll <= 1.0))
    throw core::Error("dds participant '" + name + "': poll = " + text::number(options.poll) + ": expected a period in s in (0, 1]");
  if (options.priority < 0 || options.priority > 99)
    throw core::Error("dds participant '" + name + "': priority = " + std::to_string(options.priority) +
                      ": expected a SCHED_FIFO priority 1..99, or 0 (as the creating thread)");
  if (!(options.drop_share >= 0.0 && options.drop_share <= 1.0))
    throw core::Error("dds participant '" + name + "': drop_share = " + text::number(options.drop_share) +
                      ": expected a share in [0, 1]");
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.name(name);
  for (const std::string& address : options.initial_peers) {
    rtps::Locator_t locator;
    if (!eprosima::fastrtps::rtps::IPLocator::isIPv4(address) ||
        !eprosima::fastrtps::rtps::IPLocator::setIPv4(locator, address))
      throw core::Error("dds participant '" + name + "': initial peer '" + address +
                        "' is not an IPv4 address (expected e.g. 10.0.0.2)");
    // Port 0: Fast DDS tries the well-known discovery ports of the first participants there.
    qos.wire_protocol().builtin.initialPeersList.push_back(locator);
  }
  const bool test_transport = options.drop_share > 0.0 || options.wire_tap;
  if (options.udp_only && !test_transport) {
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>());
  }
  if (test_transport) {
    auto lossy = std::make_shared<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor>();
    const auto percent = static_cast<std::uint8_t>(std::lround(options.drop_share * 100.0));
    lossy->dropDataMessagesPercentage = percent;
    lossy->dropDataFragMessagesPercentage = percent;
    if (options.wire_tap)
      lossy->messages_filter_ = [tap = options.wire_tap](rtps::CDRMessage_t& message) {
        tap(message.buffer, message.length);
        return false;  // dropped by the percentages only
      };
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(lossy);
  }
  if (options.security.enabled()) {
    // Checked here, naming the file and what is wrong: Fast DDS only says that it could not
    // create the participant.
    const CheckedSecurity checked = checkSecurity(options.security, name);
    subject_ = checked.subject;
    permissions_ = checked.files.permissions;
    for (auto& [property, value] : securityProperties(checked)) qos.properties().properties().emplace_back(property, value);
  }
  // Only the QoS statuses: with data_on_readers in the mask, Fast DDS would call this listener
  // instead of each reader's on_data_available. Discovery callbacks come whatever the mask.
  const fdds::StatusMask mask =
      fdds::StatusMask::offered_incompatible_qos() << fdds::StatusMask::requested_incompatible_qos();
  const FifoWhileCreating fifo(priority_, name);  // the threads Fast DDS makes for it inherit the priority
  participant_ = fdds::DomainParticipantFactory::get_instance()->create_participant(domain, qos, this, mask);
  if (participant_ == nullptr)
    throw core::Error("dds: cannot create the domain participant '" + name + "' on domain " + std::to_string(domain) +
                      (subject_.empty() ? std::string(" (domain ids are 0..232)")
                                        : " (domain ids are 0..232; with DDS Security: does the governance cover "
                                          "this domain, and do the permissions '" + permissions_ +
                                          "' grant '" + subject_ + "' this domain?)"));
  publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (publisher_ == nullptr || subscriber_ == nullptr) {
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
    throw core::Error("dds: cannot create the publisher and subscriber of participant '" + name + "'");
  }
  {
    // No data sharing (Fast DDS's zero-copy path between the processes of one machine, on by
    // default whatever the transports): a peer killed while it held a data-sharing segment's
    // interprocess mutex made the surviving process abort ("Interprocess mutex timeout when
    // locking. Possible deadlock: owner died without unlocking?", boost::interprocess, in
    // SplitProcedure.KillingTheProbeHostMidInsertionStopsTheNeedleSafely and a wall-clock split
    // run on a loaded machine). A lost peer must never take the other host down; samples go
    // through the transports (shared memory or UDP), which survive a killed peer.
    fdds::DataWriterQos writer_qos = publisher_->get_default_datawriter_qos();
    writer_qos.data_sharing().off();
    publisher_->set_default_datawriter_qos(writer_qos);
    fdds::DataReaderQos reader_qos = subscriber_->get_default_datareader_qos();
    reader_qos.data_sharing().off();
    subscriber_->set_default_datareader_qos(reader_qos);
  }
  if (!subject_.empty()) {
    // Refusals by access control come only in Fast DDS's log; a participant this one discovered
    // is this one's to report.
    refusal_watch_ = watchRefusals([this](const std::string& prefix, const std::string& why) {
      bool discovered = false;
      {
        std::lock_guard lock(mutex_);
        discovered = participant_names_.count(prefix) > 0;
      }
      if (discovered) refused(prefix, "its permissions were refused (" + why + ")");
    });
  }
}

void Participant::raiseThisThread() const noexcept {
  if (priority_ > 0) FifoWhileCreating::setFifo(priority_, name_);
}

Participant::~Participant() {
  if (refusal_watch_ >= 0) unwatchRefusals(refusal_watch_);
  participant_->set_listener(nullptr);
  participant_->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

fdds::Topic* Participant::acquireTopic(const EndpointInfo& info, const fdds::TypeSupport& type) {
  std::lock_guard lock(mutex_);
  auto it = topics_.find(info.topic);
  if (it != topics_.end()) {
    if (it->second.type_name != info.type_name) {
      const auto other = std::find_if(locals_.begin(), locals_.end(), [&](const Local& l) { return l.info.topic == info.topic; });
      throw core::Error("dds topic '" + info.topic + "' carries " + it->second.type_name + " in this process" +
                        (other != locals_.end() ? " (" + describeLocal(other->info) + ")" : std::string()) + ", but " +
                        info.port + " (" + info.cobra_type + ") needs " + info.type_name +
                        "; one topic carries one type: use another topic");
    }
    ++it->second.users;
    return it->second.topic;
  }
  if (participant_->find_type(info.type_name).empty() && type.register_type(participant_) != ReturnCode_t::RETCODE_OK)
    throw core::Error("dds: cannot register the type " + info.type_name);
  fdds::Topic* topic = participant_->create_topic(info.topic, info.type_name, fdds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) throw core::Error("dds: cannot create the topic '" + info.topic + "' of type " + info.type_name);
  topics_.emplace(info.topic, SharedTopic{topic, info.type_name, 1});
  return topic;
}

void Participant::releaseTopic(const std::string& name) noexcept {
  std::lock_guard lock(mutex_);
  auto it = topics_.find(name);
  if (it == topics_.end() || --it->second.users > 0) return;
  participant_->delete_topic(it->second.topic);
  topics_.erase(it);
}

EndpointInfo Participant::effective(const EndpointInfo& info) const {
  EndpointInfo out = info;
  // A clock meeting waits for every sample a peer announced. A volatile reader that matches its
  // writer after the writer's first heartbeat (its discovery packet lost, or slow) skips the
  // samples sent before: the meeting would pass without them. Transient-local ends deliver
  // them from the writer's history (a lockstep writer offers it, a lockstep reader asks for it).
  if (lockstep()) out.qos.transient_local = true;
  return out;
}

fdds::DataWriter* Participant::createWriter(const EndpointInfo& wanted, const fdds::TypeSupport& type) {
  const EndpointInfo info = effective(wanted);
  fdds::Topic* topic = acquireTopic(info, type);
  fdds::DataWriterQos qos = publisher_->get_default_datawriter_qos();
  applyQos(qos, info.qos);
  // Fast DDS's default heartbeat period is 3 s: a lost sample would wait that long for its
  // retransmission, and a clock meeting with it. 5 ms here.
  qos.reliable_writer_qos().times.heartbeatPeriod = milliseconds(5);
  qos.reliable_writer_qos().times.initialHeartbeatDelay = milliseconds(1);
  qos.reliable_writer_qos().times.nackResponseDelay = milliseconds(1);
  fdds::DataWriter* writer = publisher_->create_datawriter(topic, qos, nullptr, fdds::StatusMask::none());
  if (writer == nullptr) {
    releaseTopic(info.topic);
    throw core::Error("dds: Fast DDS refused the writer of topic '" + info.topic + "' with QoS " + info.qos.describe() +
                      refusalHint("publish", info.topic));
  }
  addLocal(info, writer);
  return writer;
}

fdds::DataReader* Participant::createReader(const EndpointInfo& wanted, const fdds::TypeSupport& type,
                                            fdds::DataReaderListener* listener) {
  const EndpointInfo info = effective(wanted);
  fdds::Topic* topic = acquireTopic(info, type);
  fdds::DataReaderQos qos = subscriber_->get_default_datareader_qos();
  applyQos(qos, info.qos);
  qos.reliable_reader_qos().times.heartbeatResponseDelay = milliseconds(1);
  fdds::DataReader* reader = subscriber_->create_datareader(topic, qos, listener, fdds::StatusMask::data_available());
  if (reader == nullptr) {
    releaseTopic(info.topic);
    throw core::Error("dds: Fast DDS refused the reader of topic '" + info.topic + "' with QoS " + info.qos.describe() +
                      refusalHint("subscribe", info.topic));
  }
  addLocal(info, reader);
  return reader;
}

void Participant::deleteWriter(fdds::DataWriter* writer) noexcept {
  const std::string topic = writer->get_topic()->get_name();
  removeLocal(writer);
  publisher_->delete_datawriter(writer);
  releaseTopic(topic);
}

void Participant::deleteReader(fdds::DataReader* reader) noexcept {
  const std::string topic = reader->get_topicdescription()->get_name();
  reader->set_listener(nullptr);
  removeLocal(reader);
  subscriber_->delete_datareader(reader);
  releaseTopic(topic);
}

void Participant::addLocal(const EndpointInfo& info, fdds::DomainEntity* entity) {
  std::vector<Report> reports;
  {
    std::lock_guard lock(mutex_);
    locals_.push_back({info, entity});
    for (const auto& [guid, remote] : remotes_)
      if (auto r = typeMismatchLocked(locals_.back(), guid, remote)) reports.push_back(std::move(*r));
    for (const auto& [unclaimed, policy] : unclaimed_qos_)
      if (unclaimed == entity) reports.push_back(qosReportLocked(locals_.back(), policy));
    std::erase_if(unclaimed_qos_, [&](const auto& u) { return u.first == entity; });
  }
  deliver(reports);
}

void Participant::removeLocal(fdds::DomainEntity* entity) noexcept {
  std::lock_guard lock(mutex_);
  std::erase_if(locals_, [&](const Local& l) { return l.entity == entity; });
  std::erase_if(unclaimed_qos_, [&](const auto& u) { return u.first == entity; });
}

std::optional<Participant::Report> Participant::typeMismatchLocked(const Local& local, const std::string& guid,
                                                                   const Remote& remote) const {
  if (remote.topic != local.info.topic || remote.writer == local.info.writer || remote.type_name == local.info.type_name)
    return std::nullopt;
  const EndpointInfo& e = local.info;
  return Report{"e_dds_type_mismatch", "type|" + e.port + "|" + guid,
                "dds topic '" + e.topic + "': the two ends' types differ: " + describeLocal(e) +
                    (e.writer ? " sends " : " expects ") + e.type_name + ", but a " +
                    (remote.writer ? "writer" : "reader") + " in participant '" + remote.participant + "' " +
                    (remote.writer ? "sends " : "expects ") + remote.type_name +
                    "; they never connect (use ports of one type on both ends, or another topic)"};
}

void Participant::remoteDiscovered(const std::string& guid, Remote remote) {
  std::vector<Report> reports;
  {
    std::lock_guard lock(mutex_);
    const std::string prefix = guid.substr(0, guid.rfind('|'));
    if (auto it = participant_names_.find(prefix); it != participant_names_.end()) remote.participant = it->second;
    else remote.participant = "?";
    for (const Local& local : locals_)
      if (auto r = typeMismatchLocked(local, guid, remote)) reports.push_back(std::move(*r));
    remotes_[guid] = std::move(remote);
  }
  deliver(reports);
}

std::string Participant::refusalHint(const char* action, const std::string& topic) const {
  if (subject_.empty()) return "";
  return ": with DDS Security, participant '" + name_ + "' ('" + subject_ + "') may " + action + " only what its permissions '" +
         permissions_ + "' grant, and they do not grant " + action + " on '" + topic + "'";
}

void Participant::on_participant_discovery(fdds::DomainParticipant*, rtps::ParticipantDiscoveryInfo&& info) {
  std::lock_guard lock(mutex_);
  const std::string prefix = text(info.info.m_guid.guidPrefix);
  participant_names_[prefix] = info.info.m_participantName.to_string();
  // A secured participant's identity token names its certificate's subject (PKI-DH: dds.cert.sn).
  if (const std::string* subject = rtps::DataHolderHelper::find_property_value(info.info.identity_token_, "dds.cert.sn"))
    participant_subjects_[prefix] = *subject;
  // Without DDS Security, discovery is the meeting; with it, the authentication's outcome is
  // (onParticipantAuthentication, refused), which may also come first.
  setStatusLocked(prefix, subject_.empty() ? DdsTransport::RemoteParticipant::Status::Admitted
                                           : DdsTransport::RemoteParticipant::Status::Discovered);
}

void Participant::onParticipantAuthentication(fdds::DomainParticipant*, rtps::ParticipantAuthenticationInfo&& info) {
  if (info.status == rtps::ParticipantAuthenticationInfo::AUTHORIZED_PARTICIPANT) {
    // Fast DDS says so once its access control granted the participant the domain.
    std::lock_guard lock(mutex_);
    setStatusLocked(text(info.guid.guidPrefix), DdsTransport::RemoteParticipant::Status::Admitted);
    return;
  }
  if (info.status != rtps::ParticipantAuthenticationInfo::UNAUTHORIZED_PARTICIPANT) return;
  refused(text(info.guid.guidPrefix),
          "it failed DDS Security's authentication (no certificate of this participant's identity CA, or none at "
          "all)");
}

void Participant::setStatusLocked(const std::string& prefix, DdsTransport::RemoteParticipant::Status status) {
  using Status = DdsTransport::RemoteParticipant::Status;
  auto [it, added] = participant_status_.emplace(prefix, status);
  // A refusal is final; discovery (again: a changed QoS) does not undo an outcome.
  if (!added && it->second != Status::Refused && status != Status::Discovered) it->second = status;
  participants_changed_.notify_all();  // also for a name discovery just told
}

DdsTransport::RemoteParticipant Participant::remoteParticipantLocked(const std::string& prefix) const {
  DdsTransport::RemoteParticipant out;
  out.guid_prefix = prefix;
  if (auto it = participant_names_.find(prefix); it != participant_names_.end()) out.name = it->second;
  if (auto it = participant_subjects_.find(prefix); it != participant_subjects_.end()) out.subject = it->second;
  if (auto it = participant_status_.find(prefix); it != participant_status_.end()) out.status = it->second;
  return out;
}

std::vector<DdsTransport::RemoteParticipant> Participant::participants() const {
  std::lock_guard lock(mutex_);
  std::vector<DdsTransport::RemoteParticipant> out;
  for (const auto& [prefix, status] : participant_status_) out.push_back(remoteParticipantLocked(prefix));
  return out;
}

std::optional<DdsTransport::RemoteParticipant> Participant::waitForParticipant(const std::string& name,
                                                                               std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  std::optional<DdsTransport::RemoteParticipant> found;
  participants_changed_.wait_for(lock, timeout, [&] {
    for (const auto& [prefix, status] : participant_status_) {
      const auto named = participant_names_.find(prefix);
      if (status == DdsTransport::RemoteParticipant::Status::Discovered || named == participant_names_.end() ||
          named->second != name)
        continue;
      found = remoteParticipantLocked(prefix);
      return true;
    }
    return false;
  });
  return found;
}

std::string Participant::guidPrefix() const { return text(participant_->guid().guidPrefix); }

void Participant::refused(const std::string& prefix, const std::string& why) {
  std::string who = "participant " + prefix;
  {
    std::lock_guard lock(mutex_);
    setStatusLocked(prefix, DdsTransport::RemoteParticipant::Status::Refused);
    if (auto it = participant_names_.find(prefix); it != participant_names_.end()) who += " '" + it->second + "'";
    if (auto it = participant_subjects_.find(prefix); it != participant_subjects_.end())
      who += " (certificate '" + it->second + "')";
  }
  deliver({Report{"e_dds_participant_refused", "refused|" + prefix,
                  "dds participant '" + name_ + "' refused " + who + ": " + why +
                      "; nothing it sends is read, nothing is sent to it",
                  prefix}});
}

void Participant::on_subscriber_discovery(fdds::DomainParticipant*, rtps::ReaderDiscoveryInfo&& info) {
  const rtps::GUID_t& guid = info.info.guid();
  if (guid.guidPrefix == participant_->guid().guidPrefix) return;  // our own end
  const std::string key = text(guid);  // "<prefix>|<entity>"
  if (info.status == rtps::ReaderDiscoveryInfo::REMOVED_READER) {
    std::lock_guard lock(mutex_);
    remotes_.erase(key);
    return;
  }
  remoteDiscovered(key, Remote{info.info.topicName().to_string(), info.info.typeName().to_string(), "", false,
                               qosOf(info.info.m_qos)});
}

void Participant::on_publisher_discovery(fdds::DomainParticipant*, rtps::WriterDiscoveryInfo&& info) {
  const rtps::GUID_t& guid = info.info.guid();
  if (guid.guidPrefix == participant_->guid().guidPrefix) return;
  const std::string key = text(guid);  // "<prefix>|<entity>"
  if (info.status == rtps::WriterDiscoveryInfo::REMOVED_WRITER) {
    std::lock_guard lock(mutex_);
    remotes_.erase(key);
    return;
  }
  remoteDiscovered(key, Remote{info.info.topicName().to_string(), info.info.typeName().to_string(), "", true,
                               qosOf(info.info.m_qos)});
}

void Participant::on_offered_incompatible_qos(fdds::DataWriter* writer, const fdds::OfferedIncompatibleQosStatus& status) {
  incompatibleQos(writer, status.last_policy_id);
}

void Participant::on_requested_incompatible_qos(fdds::DataReader* reader,
                                                const fdds::RequestedIncompatibleQosStatus& status) {
  incompatibleQos(reader, status.last_policy_id);
}

void Participant::incompatibleQos(fdds::DomainEntity* entity, std::uint32_t policy) {
  std::vector<Report> reports;
  {
    std::lock_guard lock(mutex_);
    const auto local = std::find_if(locals_.begin(), locals_.end(), [&](const Local& l) { return l.entity == entity; });
    // Fast DDS may call this from inside create_datawriter/create_datareader, before addLocal
    // knows the end: kept until it does.
    if (local == locals_.end()) unclaimed_qos_.emplace_back(entity, policy);
    else reports.push_back(qosReportLocked(*local, policy));
  }
  deliver(reports);
}

Participant::Report Participant::qosReportLocked(const Local& local, std::uint32_t policy) const {
  const EndpointInfo& e = local.info;
  // Name the far ends that cannot match this one (discovery told their QoS); all of the other
  // side when none is found (the far end was not discovered yet).
  std::string others;
  for (const bool all : {false, true}) {
    for (const auto& [guid, remote] : remotes_) {
      if (remote.topic != e.topic || remote.writer == e.writer) continue;
      const std::string why = e.writer ? incompatibility(e.qos, remote.qos) : incompatibility(remote.qos, e.qos);
      if (!all && why.empty()) continue;
      others += std::string(others.empty() ? "" : "; ") + "a " + (remote.writer ? "writer" : "reader") +
                " in participant '" + remote.participant + "' " + (remote.writer ? "offers " : "requests ") +
                remote.qos.describe(false);
    }
    if (!others.empty()) break;
  }
  if (others.empty()) others = std::string("an end of the other side ") + (e.writer ? "requests" : "offers") + " more";
  return {"e_dds_incompatible_qos", "qos|" + e.port + "|" + e.topic + "|" + std::to_string(policy),
          "dds topic '" + e.topic + "': incompatible QoS (" + policyName(policy) + "): " + describeLocal(e) +
              (e.writer ? " offers " : " requests ") + e.qos.describe(false) + ", but " + others +
              "; they never connect (a reader cannot request more than the writer offers)"};
}

void Participant::deliver(const std::vector<Report>& reports) {
  for (const Report& r : reports) {
    {
      std::lock_guard lock(mutex_);
      if (std::find(reported_.begin(), reported_.end(), r.key) != reported_.end()) continue;
      reported_.push_back(r.key);
      problems_.push_back(r.message);
    }
    if (log_) std::cerr << "cobra dds: " << r.message << std::endl;
    core::Event event;
    event.name = r.event;
    const std::string topic = r.message.substr(r.message.find('\'') + 1);
    event.source.assign(r.source.empty() ? topic.substr(0, topic.find('\'')) : r.source);
    event.stamp = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch());
    std::lock_guard lock(events_mutex_);
    events_.write(event);
    if (event_sink_) event_sink_(event);
  }
}

void Participant::setEventSink(std::function<void(const core::Event&)> sink) {
  std::lock_guard lock(events_mutex_);
  event_sink_ = std::move(sink);
}

void Participant::addWriterEnd(WriterEndHook* end) {
  std::lock_guard lock(ends_mutex_);
  writer_ends_.push_back(end);
}

void Participant::removeWriterEnd(WriterEndHook* end) noexcept {
  std::lock_guard lock(ends_mutex_);
  std::erase(writer_ends_, end);
}

void Participant::noteReleased(const std::map<rtps::GUID_t, std::int64_t>& bounds) {
  std::lock_guard lock(released_mutex_);
  for (const auto& [writer, bound] : bounds) released_[writer] = std::max(released_[writer], bound);
}

std::map<rtps::GUID_t, std::int64_t> Participant::released() const {
  std::lock_guard lock(released_mutex_);
  return released_;
}

void Participant::addReaderEnd(ReaderEndHook* end) {
  std::lock_guard lock(ends_mutex_);
  reader_ends_.push_back(end);
}

void Participant::removeReaderEnd(ReaderEndHook* end) noexcept {
  std::lock_guard lock(ends_mutex_);
  std::erase(reader_ends_, end);
}

void Participant::withEnds(
    const std::function<void(const std::vector<WriterEndHook*>&, const std::vector<ReaderEndHook*>&)>& visit) {
  std::lock_guard lock(ends_mutex_);
  visit(writer_ends_, reader_ends_);
}

int Participant::compatibleRemoteReaders(const std::string& topic, const std::string& type_name,
                                         const EndpointQos& offered) const {
  std::lock_guard lock(mutex_);
  int count = 0;
  for (const auto& [guid, remote] : remotes_)
    if (!remote.writer && remote.topic == topic && remote.type_name == type_name &&
        incompatibility(offered, remote.qos).empty())
      ++count;
  return count;
}

bool Participant::mayMatchRemoteWriter(const std::string& guid, const EndpointInfo& reader) const {
  std::lock_guard lock(mutex_);
  const auto it = remotes_.find(guid);
  if (it == remotes_.end()) return true;
  return it->second.type_name == reader.type_name && incompatibility(it->second.qos, reader.qos).empty();
}

std::string Participant::participantName(const rtps::GuidPrefix_t& prefix) const {
  std::lock_guard lock(mutex_);
  const auto it = participant_names_.find(text(prefix));
  return it == participant_names_.end() ? std::string() : it->second;
}

std::vector<std::string> Participant::problems() const {
  std::lock_guard lock(mutex_);
  return problems_;
}

bool Participant::allMatched(const std::string& topic) const {
  std::lock_guard lock(mutex_);
  bool any = false;
  for (const Local& local : locals_) {
    if (local.info.topic != topic) continue;
    any = true;
    if (local.info.writer) {
      fdds::PublicationMatchedStatus status;
      static_cast<fdds::DataWriter*>(local.entity)->get_publication_matched_status(status);
      if (status.current_count < 1) return false;
    } else {
      fdds::SubscriptionMatchedStatus status;
      static_cast<fdds::DataReader*>(local.entity)->get_subscription_matched_status(status);
      if (status.current_count < 1) return false;
    }
  }
  return any;
}

}  // namespace cobra::dds::detail
