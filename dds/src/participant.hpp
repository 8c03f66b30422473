#pragma once
// The DDS entities of one DdsTransport: a domain participant with one publisher and one
// subscriber, the topics and types of its connections, and the problem reports (type and QoS
// mismatches between the ends of a topic). Private to cobra_dds.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/port.hpp"

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

class Participant final : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  Participant(int domain, const std::string& name, bool log);
  ~Participant() override;

  /// Creates the DDS writer (reader) of a local end; types are registered and topics shared as
  /// needed. @throws core::Error when the topic carries another type in this participant or
  /// Fast DDS refuses.
  eprosima::fastdds::dds::DataWriter* createWriter(const EndpointInfo& info,
                                                   const eprosima::fastdds::dds::TypeSupport& type);
  eprosima::fastdds::dds::DataReader* createReader(const EndpointInfo& info,
                                                   const eprosima::fastdds::dds::TypeSupport& type,
                                                   eprosima::fastdds::dds::DataReaderListener* listener);
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

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  bool log_;
  mutable std::mutex mutex_;
  std::map<std::string, SharedTopic> topics_;
  std::vector<Local> locals_;
  std::map<std::string, Remote> remotes_;                 // by GUID text
  std::map<std::string, std::string> participant_names_;  // by GUID prefix text
  std::vector<std::string> problems_;
  std::vector<std::string> reported_;  // keys of problems reported once
  std::vector<std::pair<eprosima::fastdds::dds::DomainEntity*, std::uint32_t>> unclaimed_qos_;  // see incompatibleQos
  std::mutex events_mutex_;            // the events port has one writer at a time
  core::OutputPort<core::Event> events_{"ddsEvents", "problems of the dds transport: e_dds_type_mismatch, "
                                                     "e_dds_incompatible_qos (source: the topic)", ""};
};

}  // namespace cobra::dds::detail
