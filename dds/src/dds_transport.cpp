#include "cobra/dds/dds_transport.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <typeindex>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"
#include "cobra/dds/conversions.hpp"
#include "participant.hpp"

namespace cobra::dds {
namespace fdds = eprosima::fastdds::dds;
using detail::EndpointInfo;
using detail::EndpointQos;
using detail::Participant;

namespace {

constexpr const char* kQosKeys =
    "reliability (\"reliable\" or \"best_effort\"), depth (an integer >= 1), lease (s, a number > 0), "
    "durability (\"volatile\" or \"transient_local\")";

EndpointQos parseQos(const core::ConnPolicy& policy) {
  EndpointQos qos;
  qos.depth = policy.kind == core::ConnPolicy::Kind::Data ? 1 : static_cast<int>(policy.size);
  for (const auto& [key, value] : policy.options) {
    const std::string bad = "dds qos." + key + " = \"" + value + "\": expected ";
    if (key == "reliability") {
      if (value != "reliable" && value != "best_effort") throw core::Error(bad + "\"reliable\" or \"best_effort\"");
      qos.reliable = value == "reliable";
    } else if (key == "durability") {
      if (value != "volatile" && value != "transient_local") throw core::Error(bad + "\"volatile\" or \"transient_local\"");
      qos.transient_local = value == "transient_local";
    } else if (key == "depth") {
      // The port text parsers (data_type.hpp): the whole value must be the number.
      int depth = 0;
      if (!core::DataTypeTraits<int>::parse(value, depth) || depth < 1 || depth > 1000000)
        throw core::Error(bad + "an integer >= 1 (samples)");
      qos.depth = depth;
    } else if (key == "lease") {
      double lease = 0.0;
      if (!core::DataTypeTraits<double>::parse(value, lease) || !(lease > 0.0) || !std::isfinite(lease))
        throw core::Error(bad + "a number of seconds > 0, e.g. 0.1");
      qos.lease = lease;
    } else {
      throw core::Error("unknown dds qos key '" + key + "'; allowed keys: " + kQosKeys);
    }
  }
  return qos;
}

template <class T>
EndpointInfo endpointInfo(const core::PortBase& port, const core::ConnPolicy& policy, bool writer) {
  return EndpointInfo{DdsTransport::ddsTopic(policy.topic), wireTypeName<T>(), std::string(port.type().name),
                      port.fullName(), writer, parseQos(policy)};
}

template <class T>
fdds::TypeSupport typeSupport() {
  return fdds::TypeSupport(new typename Wire<T>::PubSub());
}

/// Writer's end: the port writes into the channel to `hidden_`; this end's thread looks every
/// `poll` for what arrived, converts it and publishes it (a write sets `fresh_` and makes no
/// system call: nobody waits on the flag). In lockstep the clock meeting flushes instead.
template <class T>
class WriterEnd final : public core::TransportEnd, public detail::WriterEndHook {
 public:
  WriterEnd(std::shared_ptr<Participant> participant, std::unique_ptr<core::InputPort<T>> hidden,
            fdds::DataWriter* writer, EndpointInfo info)
      : participant_(std::move(participant)), hidden_(std::move(hidden)), writer_(writer), info_(participant_->effective(info)) {
    hidden_->setNewDataFlag(&fresh_);
  }
  ~WriterEnd() override { close(); }

  core::InputPort<T>& hidden() { return *hidden_; }
  void start() {
    participant_->addWriterEnd(this);
    thread_ = std::thread([this] { run(); });
  }

  void close() noexcept override {
    if (writer_ == nullptr) return;
    participant_->removeWriterEnd(this);
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    participant_->deleteWriter(writer_);
    writer_ = nullptr;
  }

  void flush() noexcept override {
    fresh_.store(false);
    drain();
  }
  std::int64_t published() const noexcept override { return published_.load(); }
  fdds::DataWriter* writer() const noexcept override { return writer_; }
  const EndpointInfo& info() const noexcept override { return info_; }

 private:
  void run() {
    participant_->raiseThisThread();
    const auto poll = participant_->poll();
    while (!stop_.load()) {
      std::this_thread::sleep_for(poll);
      if (participant_->lockstep() || !fresh_.load()) continue;
      fresh_.store(false);  // before draining: a sample written during the drain sets it again
      drain();
    }
  }

  /// Publishes what the channel holds; the thread's poll and a meeting's flush may both call it.
  void drain() noexcept {
    std::lock_guard lock(drain_mutex_);
    while (hidden_->readNew(value_) == core::FlowStatus::NewData) {
      toMsg(value_, msg_);
      // Keyless types, no dispose: the writer's sequence numbers are its writes, 1, 2, ...
      if (writer_->write(&msg_)) published_.fetch_add(1);
    }
  }

  std::shared_ptr<Participant> participant_;
  std::unique_ptr<core::InputPort<T>> hidden_;
  fdds::DataWriter* writer_;
  EndpointInfo info_;
  std::mutex drain_mutex_;
  typename Wire<T>::Msg msg_;  // under drain_mutex_
  T value_{};                  // under drain_mutex_
  std::atomic<std::int64_t> published_{0};
  std::atomic<bool> fresh_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// Reader's end: Fast DDS's listener converts each sample and writes it through `hidden_` into
/// the channel the input port reads; in lockstep it holds the samples until the clock meeting
/// releases them.
template <class T>
class ReaderEnd final : public core::TransportEnd, public fdds::DataReaderListener, public detail::ReaderEndHook {
 public:
  ReaderEnd(std::shared_ptr<Participant> participant, std::unique_ptr<core::OutputPort<T>> hidden, EndpointInfo info)
      : participant_(std::move(participant)), hidden_(std::move(hidden)), info_(participant_->effective(info)) {}
  ~ReaderEnd() override { close(); }

  core::OutputPort<T>& hidden() { return *hidden_; }
  /// Creates the DDS reader once the channel to the input port exists (samples may arrive at once).
  void start() {
    floor_ = participant_->released();
    participant_->addReaderEnd(this);
    reader_ = participant_->createReader(info_, typeSupport<T>(), this);
  }

  void close() noexcept override {
    {
      std::lock_guard lock(mutex_);  // waits for a listener call in progress
      if (closed_) return;
      closed_ = true;
    }
    participant_->removeReaderEnd(this);
    if (reader_ != nullptr) participant_->deleteReader(reader_);
    reader_ = nullptr;
  }

  void on_data_available(fdds::DataReader* reader) override {
    std::lock_guard lock(mutex_);  // Fast DDS may call from several receive threads
    if (closed_) return;
    fdds::SampleInfo info;
    const bool hold = participant_->lockstep();
    while (reader->take_next_sample(&msg_, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      fromMsg(msg_, value_);
      const auto& writer = info.sample_identity.writer_guid();
      const auto sequence = info.sample_identity.sequence_number().to64long();
      std::int64_t& highest = received_[writer];  // one node per far writer, on its first sample
      highest = std::max<std::int64_t>(highest, static_cast<std::int64_t>(sequence));
      if (!hold) {
        hidden_->write(value_);
      } else if (const auto floor = floor_.find(writer);
                 floor == floor_.end() || static_cast<std::int64_t>(sequence) > floor->second) {
        held_.push_back({writer, static_cast<std::int64_t>(sequence), value_});
      }
    }
  }

  std::int64_t received(const eprosima::fastrtps::rtps::GUID_t& writer) const override {
    std::lock_guard lock(mutex_);
    const auto it = received_.find(writer);
    return it == received_.end() ? 0 : it->second;
  }

  void release(const std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t>& bounds) override {
    std::lock_guard lock(mutex_);
    std::erase_if(held_, [&](const Held& h) {
      const auto bound = bounds.find(h.writer);
      if (bound != bounds.end() && h.sequence > bound->second) return false;
      hidden_->write(h.value);
      return true;
    });
  }
  const EndpointInfo& info() const noexcept override { return info_; }

 private:
  struct Held {
    eprosima::fastrtps::rtps::GUID_t writer;
    std::int64_t sequence;
    T value;
  };
  std::shared_ptr<Participant> participant_;
  std::unique_ptr<core::OutputPort<T>> hidden_;
  EndpointInfo info_;
  fdds::DataReader* reader_ = nullptr;
  mutable std::mutex mutex_;
  bool closed_ = false;
  typename Wire<T>::Msg msg_;
  T value_{};
  std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t> received_;
  std::vector<Held> held_;  // lockstep: in arrival order
  // Lockstep: per far writer, the samples released before this end existed (never delivered).
  std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t> floor_;
};

struct Binding {
  std::function<void(const std::shared_ptr<Participant>&, core::OutputPortBase&, const core::ConnPolicy&, core::PortBase*)>
      make_writer;
  std::function<void(const std::shared_ptr<Participant>&, core::InputPortBase&, const core::ConnPolicy&, core::PortBase*)>
      make_reader;
};

template <class T>
Binding binding() {
  Binding b;
  b.make_writer = [](const std::shared_ptr<Participant>& participant, core::OutputPortBase& output,
                     const core::ConnPolicy& policy, core::PortBase* peer) {
    const EndpointInfo info = endpointInfo<T>(output, policy, true);
    std::unique_ptr<core::InputPort<T>> hidden(
        static_cast<core::InputPort<T>*>(output.makeReader("dds:" + info.topic, "writer's end of a dds connection").release()));
    fdds::DataWriter* writer = participant->createWriter(info, typeSupport<T>());
    auto end = std::make_shared<WriterEnd<T>>(participant, std::move(hidden), writer, info);
    core::attachTransportEnd(output, end->hidden(), policy, end, peer);
    end->start();
  };
  b.make_reader = [](const std::shared_ptr<Participant>& participant, core::InputPortBase& input,
                     const core::ConnPolicy& policy, core::PortBase* peer) {
    const EndpointInfo info = endpointInfo<T>(input, policy, false);
    std::unique_ptr<core::OutputPort<T>> hidden(
        static_cast<core::OutputPort<T>*>(input.makeWriter("dds:" + info.topic, "reader's end of a dds connection").release()));
    auto end = std::make_shared<ReaderEnd<T>>(participant, std::move(hidden), info);
    core::attachTransportEnd(input, end->hidden(), policy, end, peer);
    end->start();
  };
  return b;
}

const std::map<std::type_index, Binding>& bindings() {
  static const std::map<std::type_index, Binding> table = {
      {typeid(double), binding<double>()},
      {typeid(int), binding<int>()},
      {typeid(bool), binding<bool>()},
      {typeid(std::string), binding<std::string>()},
      {typeid(std::vector<double>), binding<std::vector<double>>()},
      {typeid(KDL::Vector), binding<KDL::Vector>()},
      {typeid(KDL::Rotation), binding<KDL::Rotation>()},
      {typeid(KDL::Frame), binding<KDL::Frame>()},
      {typeid(KDL::Twist), binding<KDL::Twist>()},
      {typeid(KDL::Wrench), binding<KDL::Wrench>()},
      {typeid(KDL::JntArray), binding<KDL::JntArray>()},
      {typeid(core::Event), binding<core::Event>()},
      {typeid(core::TaskState), binding<core::TaskState>()},
  };
  return table;
}

const Binding& bindingOf(const core::PortBase& port) {
  const auto& table = bindings();
  auto it = table.find(port.type().id);
  if (it == table.end())
    throw core::Error("the dds transport carries no " + std::string(port.type().name) +
                      "; it carries double, int, bool, string, vector<double>, KDL.Vector, KDL.Rotation, KDL.Frame, "
                      "KDL.Twist, KDL.Wrench, KDL.JntArray, Event and TaskState");
  return it->second;
}

}  // namespace

DdsTransport::DdsTransport(Options options)
    : participant_(std::make_shared<Participant>(options)) {}

DdsTransport::~DdsTransport() = default;

std::string DdsTransport::ddsTopic(const std::string& topic) {
  const std::string name = !topic.empty() && topic.front() == '/' ? topic.substr(1) : topic;
  const bool valid = !name.empty() && std::isdigit(static_cast<unsigned char>(name.front())) == 0 &&
                     name.back() != '/' && name.find("//") == std::string::npos &&
                     std::all_of(name.begin(), name.end(), [](unsigned char c) {
                       return std::isalnum(c) != 0 || c == '_' || c == '/';
                     });
  if (!valid)
    throw core::Error("dds topic '" + topic +
                      "' is not a ROS 2 topic name: expected letters, digits and '_' in '/'-separated parts, "
                      "not starting with a digit, e.g. \"needle/pose\"");
  return "rt/" + name;
}

void DdsTransport::check(const core::ConnPolicy& policy) const {
  ddsTopic(policy.topic);
  parseQos(policy);
}

void DdsTransport::makeWriterEnd(core::OutputPortBase& output, const core::ConnPolicy& policy, core::PortBase* peer) {
  check(policy);
  bindingOf(output).make_writer(participant_, output, policy, peer);
}

void DdsTransport::makeReaderEnd(core::InputPortBase& input, const core::ConnPolicy& policy, core::PortBase* peer) {
  check(policy);
  bindingOf(input).make_reader(participant_, input, policy, peer);
}

core::OutputPort<core::Event>& DdsTransport::events() { return participant_->events(); }

std::vector<std::string> DdsTransport::problems() const { return participant_->problems(); }

bool DdsTransport::waitForMatch(const std::string& topic, std::chrono::milliseconds timeout) const {
  const std::string name = ddsTopic(topic);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!participant_->allMatched(name)) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

std::shared_ptr<DdsTransport> registerDdsTransport(DdsTransport::Options options, const std::string& name) {
  const std::string doc = "Fast DDS, domain " + std::to_string(options.domain);
  auto transport = std::make_shared<DdsTransport>(std::move(options));
  core::TransportRegistry::add(name, doc, "cobra_dds", transport);
  return transport;
}

}  // namespace cobra::dds
