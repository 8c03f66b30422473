#pragma once
// The DDS entities of one DdsTransport: a domain participant with one publisher and one
// subscriber, the topics and types of its connections, and the problem reports (type and QoS
// mismatches between the ends of a topic). Not part of the API: in a header only because the
// ends of a connection (detail/ends.hpp) are templates that registerDdsType<T>() instantiates.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/port.hpp"
#include "cobra/dds/dds_transport.hpp"

namespace cobra::dds::detail {

/// The QoS a connection asks for (`qos = {...}` of its policy).
struct EndpointQos {
  bool reliable = true;
  bool transient_local = false;
  int depth = 1;
  double lease = 0.0;  ///< s; 0 = infinite

  /// "reliable, volatile, depth 16, lease 0.1 s" (depth only when `with_depth`).
  std::string describe(bool with_depth = true) const;
};

/// What a local end is, for messages: "the writer of Gen.out (KDL.Frame)".
struct EndpointInfo {
  std::string topic;      ///< DDS topic, "rt/..."
  std::string type_name;  ///< DDS type name
  std::string cobra_type;
  std::string port;  ///< full name of the cobra port
  bool writer = true;
  EndpointQos qos;
};

/// A local writer end as the clock meeting (DdsLink) sees it.
class WriterEndHook {
 public:
  /// Publishes every sample the end's channel holds, on the caller's thread.
  virtual void flush() noexcept = 0;
  /// The DDS sequence number of the last sample the end published (0: none yet).
  virtual std::int64_t published() const noexcept = 0;
  virtual eprosima::fastdds::dds::DataWriter* writer() const noexcept = 0;
  virtual const EndpointInfo& info() const noexcept = 0;

 protected:
  ~WriterEndHook() = default;
};

/// A local reader end as the clock meeting sees it.
class ReaderEndHook {
 public:
  /// The highest sequence number received from `writer` (0: none).
  virtual std::int64_t received(const eprosima::fastrtps::rtps::GUID_t& writer) const = 0;
  /// In lockstep: writes into the input port's channel the samples held back so far whose
  /// sequence number is at most `bounds[writer]` (all of a writer missing from `bounds`).
  virtual void release(const std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t>& bounds) = 0;
  virtual const EndpointInfo& info() const noexcept = 0;

 protected:
  ~ReaderEndHook() = default;
};

class Participant final : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  explicit Participant(const DdsTransport::Options& options);
  ~Participant() override;

  eprosima::fastdds::dds::DomainParticipant* entity() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  /// Period at which a writer end's thread looks for samples to send (wall-clock runs).
  std::chrono::nanoseconds poll() const { return poll_; }
  /// Puts the calling thread (a writer end's) at the participant's SCHED_FIFO priority, if any.
  void raiseThisThread() const noexcept;

  /// Lockstep: writer ends send only when the clock meeting flushes them, reader ends hold what
  /// arrives until the meeting releases it (so that a sample written in [t - d, t) is read from
  /// t on, whichever process runs ahead). Set by DdsLink before the first step.
  void setLockstep(bool lockstep) { lockstep_.store(lockstep); }
  bool lockstep() const { return lockstep_.load(); }
  void addWriterEnd(WriterEndHook* end);
  void removeWriterEnd(WriterEndHook* end) noexcept;
  /// Lockstep: a meeting released the samples of each far writer up to `bounds` (sequence
  /// numbers); kept as the highest per writer.
  void noteReleased(const std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t>& bounds);
  /// What the meetings released so far: a reader end made mid-run ignores those samples (they
  /// were written before it existed; a transient-local reader is sent them again).
  std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t> released() const;
  void addReaderEnd(ReaderEndHook* end);
  void removeReaderEnd(ReaderEndHook* end) noexcept;
  /// Runs `visit` with the lists of local ends, holding the lock that keeps them alive.
  void withEnds(const std::function<void(const std::vector<WriterEndHook*>&, const std::vector<ReaderEndHook*>&)>& visit);
  /// Remote readers on `topic` that discovery announced with `type_name` and a QoS that a
  /// writer offering `offered` satisfies: the readers a writer end should be matched with.
  int compatibleRemoteReaders(const std::string& topic, const std::string& type_name, const EndpointQos& offered) const;
  /// False when discovery announced the remote writer `guid` (text) with another type than
  /// `reader`'s or a QoS it cannot match; true when compatible or not announced yet.
  bool mayMatchRemoteWriter(const std::string& guid, const EndpointInfo& reader) const;
  /// The name of the participant with this GUID prefix, as discovery told it ("" if unknown).
  std::string participantName(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) const;
  /// This participant's GUID prefix as text ("01.0f.78.fd.e1.70.99.80.00.00.00.00").
  std::string guidPrefix() const;
  /// DdsTransport::participants() and waitForParticipant().
  std::vector<DdsTransport::RemoteParticipant> participants() const;
  std::optional<DdsTransport::RemoteParticipant> waitForParticipant(const std::string& name,
                                                                    std::chrono::milliseconds timeout) const;
  /// Also sends each problem event to `sink` (DdsLink forwards them on its events port);
  /// nullptr: none.
  void setEventSink(std::function<void(const core::Event&)> sink);

  /// Creates the DDS writer (reader) of a local end; types are registered and topics shared as
  /// needed. @throws core::Error when the topic carries another type in this participant or
  /// Fast DDS refuses. In lockstep both are transient-local whatever `info` asks (see effective).
  eprosima::fastdds::dds::DataWriter* createWriter(const EndpointInfo& info,
                                                   const eprosima::fastdds::dds::TypeSupport& type);
  eprosima::fastdds::dds::DataReader* createReader(const EndpointInfo& info,
                                                   const eprosima::fastdds::dds::TypeSupport& type,
                                                   eprosima::fastdds::dds::DataReaderListener* listener);
  /// `info` as this participant makes its end: transient-local in lockstep.
  EndpointInfo effective(const EndpointInfo& info) const;
  void deleteWriter(eprosima::fastdds::dds::DataWriter* writer) noexcept;
  void deleteReader(eprosima::fastdds::dds::DataReader* reader) noexcept;

  core::OutputPort<core::Event>& events() { return events_; }
  std::vector<std::string> problems() const;
  bool allMatched(const std::string& topic) const;

  // DomainParticipantListener: discovery (type checks) and incompatible QoS (from Fast DDS).
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  void on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override;
  void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;
  void on_offered_incompatible_qos(eprosima::fastdds::dds::DataWriter* writer,
                                   const eprosima::fastdds::dds::OfferedIncompatibleQosStatus& status) override;
  void on_requested_incompatible_qos(eprosima::fastdds::dds::DataReader* reader,
                                     const eprosima::fastdds::dds::RequestedIncompatibleQosStatus& status) override;
  /// DDS Security: a remote participant refused (authentication or access control) is reported
  /// once (`e_dds_participant_refused`, source: its GUID prefix), naming what discovery said of
  /// it (its name, its certificate's subject).
  void onParticipantAuthentication(eprosima::fastdds::dds::DomainParticipant* participant,
                                   eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override;
  /// This participant's certificate subject (RFC 2253); "" without DDS Security.
  const std::string& subject() const { return subject_; }

 private:
  struct Remote {
    std::string topic, type_name, participant;
    bool writer = true;
    EndpointQos qos;
  };
  struct Local {
    EndpointInfo info;
    eprosima::fastdds::dds::DomainEntity* entity;
  };
  struct SharedTopic {
    eprosima::fastdds::dds::Topic* topic;
    std::string type_name;
    int users = 0;
  };

  eprosima::fastdds::dds::Topic* acquireTopic(const EndpointInfo& info, const eprosima::fastdds::dds::TypeSupport& type);
  void releaseTopic(const std::string& name) noexcept;
  void addLocal(const EndpointInfo& info, eprosima::fastdds::dds::DomainEntity* entity);
  void removeLocal(eprosima::fastdds::dds::DomainEntity* entity) noexcept;
  struct Report {
    const char* event;
    std::string key;  ///< a problem is reported once per key
    std::string message;
    std::string source = {};  ///< the event's source; "" = the first name quoted in the message (the topic)
  };
  void remoteDiscovered(const std::string& guid, Remote remote);
  /// The report of a type mismatch between `local` and `remote`, if they are two sides of one
  /// topic with different types.
  std::optional<Report> typeMismatchLocked(const Local& local, const std::string& guid, const Remote& remote) const;
  void incompatibleQos(eprosima::fastdds::dds::DomainEntity* entity, std::uint32_t policy);
  /// The report of Fast DDS's incompatible `policy` for `local`, naming the far ends' QoS.
  Report qosReportLocked(const Local& local, std::uint32_t policy) const;
  /// Keeps, logs and sends the reports not seen before. Called without the lock held.
  void deliver(const std::vector<Report>& reports);
  /// Reports the refused remote participant `prefix` once (`why`: what failed).
  void refused(const std::string& prefix, const std::string& why);
  /// Sets the outcome of the remote participant `prefix` (never back from Refused) and wakes
  /// waitForParticipant. Called with mutex_ held.
  void setStatusLocked(const std::string& prefix, DdsTransport::RemoteParticipant::Status status);
  DdsTransport::RemoteParticipant remoteParticipantLocked(const std::string& prefix) const;
  /// For a refused writer or reader: what the permissions say ("" without DDS Security).
  std::string refusalHint(const char* action, const std::string& topic) const;

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  std::chrono::nanoseconds poll_;
  int priority_;  // SCHED_FIFO 1..99 of its threads; 0: as their creator's
  std::string name_;
  std::string subject_;      // DDS Security: the certificate's subject; "" without
  std::string permissions_;  // DDS Security: the permissions file (for messages); "" without
  int refusal_watch_ = -1;   // DDS Security: the id of its watch of Fast DDS's log (security.hpp)
  std::atomic<bool> lockstep_{false};
  mutable std::mutex released_mutex_;
  std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t> released_;  // under released_mutex_
  std::mutex ends_mutex_;
  std::vector<WriterEndHook*> writer_ends_;
  std::vector<ReaderEndHook*> reader_ends_;
  std::function<void(const core::Event&)> event_sink_;  // under events_mutex_
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  bool log_;
  mutable std::mutex mutex_;
  std::map<std::string, SharedTopic> topics_;
  std::vector<Local> locals_;
  std::map<std::string, Remote> remotes_;                 // by GUID text
  std::map<std::string, std::string> participant_names_;  // by GUID prefix text
  std::map<std::string, std::string> participant_subjects_;  // by GUID prefix: its identity token's certificate subject
  std::map<std::string, DdsTransport::RemoteParticipant::Status> participant_status_;  // by GUID prefix
  mutable std::condition_variable participants_changed_;  // with mutex_: a participant's status changed
  std::vector<std::string> problems_;
  std::vector<std::string> reported_;  // keys of problems reported once
  std::vector<std::pair<eprosima::fastdds::dds::DomainEntity*, std::uint32_t>> unclaimed_qos_;  // see incompatibleQos
  std::mutex events_mutex_;            // the events port has one writer at a time
  core::OutputPort<core::Event> events_{"ddsEvents", "problems of the dds transport: e_dds_type_mismatch, "
                                                     "e_dds_incompatible_qos (source: the topic)", ""};
};

}  // namespace cobra::dds::detail
